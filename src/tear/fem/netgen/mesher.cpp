// fem/'s netgen half (fem/mesher.h): a closed surface (3D) or a boundary (2D) meshed by nglib.
// Built as the module libtear_netgen.so; the only file that includes netgen.
#include "tear/fem/mesher.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>

namespace nglib {
#include <nglib.h>
}

namespace tear {

namespace {

// netgen reports its progress on standard output: sent to /dev/null while it meshes, so that
// tear's own output (and a frame written to stdout) stays clean.
class QuietStdout {
 public:
  QuietStdout() {
    std::cout.flush();
    std::fflush(stdout);
    saved_ = dup(1);
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) dup2(null, 1);
    if (null >= 0) ::close(null);
  }
  ~QuietStdout() {
    std::cout.flush();
    std::fflush(stdout);
    if (saved_ >= 0) {
      dup2(saved_, 1);
      ::close(saved_);
    }
  }

 private:
  int saved_ = -1;
};

void parameters(const MeshRequest& r, nglib::Ng_Meshing_Parameters* mp) {
  mp->maxh = r.max_h;
  mp->minh = 0;
  mp->fineness = 0.5;
  mp->grading = 0.3;
  mp->optsurfmeshenable = 1;
  mp->optvolmeshenable = 1;
}

MeshResult mesh_3d(const MeshRequest& r) {
  using namespace nglib;
  MeshResult out;
  Ng_STL_Geometry* geom = Ng_STL_NewGeometry();
  for (const std::array<int, 3>& t : r.triangles) {
    double p[3][3];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) p[k][a] = r.points[size_t(t[size_t(k)])][a];
    Ng_STL_AddTriangle(geom, p[0], p[1], p[2]);
  }
  Ng_Mesh* mesh = Ng_NewMesh();
  Ng_Meshing_Parameters mp;
  parameters(r, &mp);
  if (Ng_STL_InitSTLGeometry(geom) != NG_OK)
    out.error = "netgen could not read the surface (not closed, or triangles overlap)";
  else if (Ng_STL_MakeEdges(geom, mesh, &mp) != NG_OK)
    out.error = "netgen could not find the surface's edges";
  else if (Ng_STL_GenerateSurfaceMesh(geom, mesh, &mp) != NG_OK)
    out.error = "netgen could not remesh the surface at this mesh size";
  else if (Ng_GenerateVolumeMesh(mesh, &mp) != NG_OK)
    out.error = "netgen could not fill the surface with tetrahedra";
  if (out.error.empty()) {
    const int np = Ng_GetNP(mesh), ne = Ng_GetNE(mesh);
    out.nodes.resize(size_t(np));
    for (int i = 0; i < np; ++i) Ng_GetPoint(mesh, i + 1, out.nodes[size_t(i)].data());
    out.elements.resize(size_t(ne));
    for (int e = 0; e < ne; ++e) {
      int p[10];
      if (Ng_GetVolumeElement(mesh, e + 1, p) != NG_TET) {
        out.error = "netgen made an element other than a tetrahedron";
        break;
      }
      for (int k = 0; k < 4; ++k) out.elements[size_t(e)][size_t(k)] = p[k] - 1;
    }
  }
  Ng_DeleteMesh(mesh);
  // (nglib 6.2 has no Ng_STL_DeleteGeometry: the geometry is left to the process)
  return out;
}

// nglib 6.2 reads 2D geometry from a file only: the boundary as its "splinecurves2dv2" text.
// Segments meet at shared points (the same coordinates, bit for bit, are one point).
std::string in2d_text(const MeshRequest& r) {
  std::ostringstream s;
  s.precision(17);
  s << "splinecurves2dv2\n5\n\npoints\n";
  std::map<std::pair<double, double>, int> ids;
  const auto point = [&](const Eigen::Vector2d& p) {
    const auto [it, fresh] = ids.emplace(std::make_pair(p.x(), p.y()), int(ids.size()) + 1);
    if (fresh) s << it->second << " " << p.x() << " " << p.y() << "\n";
    return it->second;
  };
  std::ostringstream segs;
  for (const BoundarySegment2& g : r.segments) {
    const int a = point(g.a);
    if (g.arc) {
      const int c = point(g.c);
      segs << "1 0 3 " << a << " " << c << " " << point(g.b) << "\n";
    } else {
      segs << "1 0 2 " << a << " " << point(g.b) << "\n";
    }
  }
  s << "\nsegments\n" << segs.str() << "\nmaterials\n1 domain -maxh=" << r.max_h << "\n";
  return s.str();
}

MeshResult mesh_2d(const MeshRequest& r) {
  using namespace nglib;
  MeshResult out;
  char name[] = "/tmp/tear-netgen-XXXXXX";
  const int fd = mkstemp(name);
  if (fd < 0) {
    out.error = "could not write netgen's geometry file in /tmp";
    return out;
  }
  ::close(fd);
  const std::string path = std::string(name) + ".in2d";
  std::filesystem::rename(name, path);
  {
    std::ofstream f(path);
    f << in2d_text(r);
  }
  Ng_Geometry_2D* geom = Ng_LoadGeometry_2D(path.c_str());
  std::filesystem::remove(path);
  if (!geom) {
    out.error = "netgen could not read the boundary";
    return out;
  }
  Ng_Meshing_Parameters mp;
  parameters(r, &mp);
  Ng_Mesh* mesh = nullptr;
  if (Ng_GenerateMesh_2D(geom, &mesh, &mp) != NG_OK || !mesh) {
    out.error = "netgen could not mesh the region at this mesh size";
    return out;
  }
  const int np = Ng_GetNP_2D(mesh), ne = Ng_GetNE_2D(mesh);
  out.nodes.resize(size_t(np));
  for (int i = 0; i < np; ++i) {
    double x[2];
    Ng_GetPoint_2D(mesh, i + 1, x);
    out.nodes[size_t(i)] = Eigen::Vector3d(x[0], x[1], 0);
  }
  out.elements.resize(size_t(ne));
  for (int e = 0; e < ne; ++e) {
    int p[8];
    if (Ng_GetElement_2D(mesh, e + 1, p) != NG_TRIG) {
      out.error = "netgen made an element other than a triangle";
      break;
    }
    out.elements[size_t(e)] = {p[0] - 1, p[1] - 1, p[2] - 1, -1};
  }
  Ng_DeleteMesh(mesh);
  return out;
}

MeshResult mesh(const MeshRequest& r) {
  static std::mutex mutex;  // netgen keeps global state
  const std::lock_guard<std::mutex> lock(mutex);
  static bool initialised = false;
  if (!initialised) {
    nglib::Ng_Init();
    initialised = true;
  }
  const QuietStdout quiet;
  try {
    return r.dim == 2 ? mesh_2d(r) : mesh_3d(r);
  } catch (const std::exception& e) {
    MeshResult out;
    out.error = std::string("netgen failed: ") + e.what();
    return out;
  } catch (...) {
    MeshResult out;
    out.error = "netgen failed";
    return out;
  }
}

const char* version() { return "netgen 6.2 (nglib)"; }

const NetgenModule kModule{kNetgenAbi, &mesh, &version};

}  // namespace

}  // namespace tear

extern "C" __attribute__((visibility("default"))) const tear::NetgenModule* tear_netgen_module() {
  return &tear::kModule;
}
