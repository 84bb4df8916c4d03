// Ray tracing a frame with Embree 3: spheres (or the surface mesh) over an analytic ground plane,
// a soft key light with shadows and a sky with ambient occlusion; a few samples per pixel from
// a low-discrepancy sequence rotated per pixel, so every pixel is computed on its own and the
// picture does not depend on the thread count. Colliders are composited over what each ray sees
// (collider_layer.h).
#include "tear/exec/parallel.h"
#include "tear/render/collider_layer.h"
#include "tear/render/color_map.h"
#include "tear/render/legend.h"
#include "tear/render/render.h"

#include "tear/surface/mesher.h"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace tear {

using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Lighting, in linear units: the key light's irradiance at normal incidence and its angular
// radius (soft shadows), the sky's radiance at the zenith and the horizon (a white overcast
// sky keeps the colour map's hues), and light bounced off the ground.
constexpr double kKey = 0.8, kKeyConeDeg = 7;
constexpr double kSkyZenith = 0.5, kSkyHorizon = 0.36, kBounce = 0.12;
// Ambient occlusion reach, in units of the first frame's size.
constexpr double kAoReach = 0.35;
// sRGB colours of the background (top and bottom of the picture) and of the ground.
const Vector3f kBackgroundTop(0.58f, 0.66f, 0.76f), kBackgroundBottom(0.93f, 0.94f, 0.95f);
constexpr float kGroundAlbedo = 0.78f;

// An integer finaliser (the "lowbias32" constants of Wellons' hash prospector).
inline uint32_t mix32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x21f0aaadu;
  x ^= x >> 15;
  x *= 0x735a2d97u;
  x ^= x >> 15;
  return x;
}
inline double unit(uint32_t h) { return double(h >> 8) * (1.0 / 16777216.0); }

// Sample `s` of a 2D R2 sequence (Roberts 2018) rotated by a per-pixel, per-use offset.
struct Sampler {
  uint32_t seed;
  Eigen::Vector2d get(int s, uint32_t use) const {
    constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
    const double ox = unit(mix32(seed ^ (0x9e3779b9u * (2 * use + 1))));
    const double oy = unit(mix32(seed ^ (0x85ebca6bu * (2 * use + 2))));
    const double x = ox + a1 * (s + 1), y = oy + a2 * (s + 1);
    return {x - std::floor(x), y - std::floor(y)};
  }
};

// Orthonormal t, b around unit n (Duff et al. 2017's branch-free construction).
void tangents(const Vector3d& n, Vector3d* t, Vector3d* b) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1 / (sign + n.z());
  const double c = n.x() * n.y() * a;
  *t = Vector3d(1 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  *b = Vector3d(c, sign + n.y() * n.y() * a, -n.y());
}

// Display colour of every point for the chosen map.
std::vector<Vector3f> point_albedo(const PointTable& frame, const RenderSettings& settings) {
  std::vector<Vector3f> out(frame.count);
  const double top = settings.range_max > 0 ? settings.range_max : 1;
  auto need = [&](const char* name) -> const std::vector<double>& {
    if (!frame.has(name))
      throw std::runtime_error(std::string("--color ") + color_by_name(settings.color) +
                               ": the frame has no column '" + name + "'");
    return frame.column(name);
  };
  switch (settings.color) {
    case ColorBy::Damage: {
      const std::vector<double>& d = need("damage");
      for (size_t i = 0; i < frame.count; ++i) out[i] = linear_rgb(damage_color(float(d[i])));
      break;
    }
    case ColorBy::Material: {
      const std::vector<double>& m = need("material");
      for (size_t i = 0; i < frame.count; ++i) out[i] = linear_rgb(material_color(int(m[i])));
      break;
    }
    case ColorBy::Fibers: {
      const std::vector<double>&fx = need("fx"), &fy = need("fy");
      const std::vector<double>* fz = frame.has("fz") ? &frame.column("fz") : nullptr;
      for (size_t i = 0; i < frame.count; ++i)
        out[i] = linear_rgb(fiber_color(float(fx[i]), float(fy[i]), fz ? float((*fz)[i]) : 0.0f));
      break;
    }
    case ColorBy::Velocity: {
      const std::vector<double>&vx = need("vx"), &vy = need("vy");
      const std::vector<double>* vz = frame.has("vz") ? &frame.column("vz") : nullptr;
      for (size_t i = 0; i < frame.count; ++i) {
        const double a = float(vx[i]), b = float(vy[i]), c = vz ? float((*vz)[i]) : 0.0f;
        out[i] = linear_rgb(viridis_color(std::sqrt(a * a + b * b + c * c) / top));
      }
      break;
    }
    case ColorBy::DrivingForce: {
      const std::vector<double>& D = need("driving_force");
      for (size_t i = 0; i < frame.count; ++i)
        out[i] = linear_rgb(driving_force_color(float(D[i]) / top));
      break;
    }
    case ColorBy::DamageLaplacian: {
      const std::vector<double>& L = need("damage_laplacian");
      for (size_t i = 0; i < frame.count; ++i)
        out[i] = linear_rgb(diverging_color(float(L[i]) / top));
      break;
    }
  }
  return out;
}

// The frame column a colour map reads first.
const char* map_column(ColorBy c) {
  switch (c) {
    case ColorBy::Fibers: return "fx";
    case ColorBy::Velocity: return "vx";
    default: return color_by_name(c);
  }
}

// Display colour of a codimensional mesh's vertices: by the map where the vertices have its
// columns (material and velocity: cloth, yarn and hair have no damage or fibers), else by
// their material's colour.
std::vector<Vector3f> mesh_albedo(const PointTable& vertices, const RenderSettings& settings) {
  if (vertices.has(map_column(settings.color))) return point_albedo(vertices, settings);
  std::vector<Vector3f> out(vertices.count, linear_rgb(material_color(0)));
  if (vertices.has("material")) {
    const std::vector<double>& m = vertices.column("material");
    for (size_t i = 0; i < vertices.count; ++i) out[i] = linear_rgb(material_color(int(m[i])));
  }
  return out;
}

// What a camera ray found.
struct Surface {
  Vector3d p;
  Vector3d n;   // shading normal, on the side of the eye
  Vector3d ng;  // geometric normal, on the side of the eye (where secondary rays start)
  Vector3f albedo;
  bool codim = false;  // on a codimensional mesh (cloth, yarn, hair)
};

}  // namespace

struct Renderer::Device {
  RTCDevice device = nullptr;
  std::mutex error_mutex;
  std::string error;

  Device() {
    device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(
        device,
        [](void* user, RTCError, const char* message) {
          Device* self = static_cast<Device*>(user);
          std::lock_guard<std::mutex> lock(self->error_mutex);
          if (self->error.empty()) self->error = message ? message : "unknown error";
        },
        this);
  }
  ~Device() { rtcReleaseDevice(device); }
  void check() {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (!error.empty()) {
      const std::string e = "Embree: " + error;
      error.clear();
      throw std::runtime_error(e);
    }
  }
};

const char* embree_version() { return RTC_VERSION_STRING; }

Renderer::Renderer() : device_(std::make_unique<Device>()) {}
Renderer::~Renderer() = default;

namespace {

// Embree handles released when their owner goes, an exception included (a Geometry whose
// constructor throws after creating its scene has no destructor run).
struct ReleaseScene {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
struct ReleaseGeometry {
  void operator()(RTCGeometry g) const { rtcReleaseGeometry(g); }
};
using SceneHandle = std::unique_ptr<RTCSceneTy, ReleaseScene>;
using GeometryHandle = std::unique_ptr<RTCGeometryTy, ReleaseGeometry>;

// A new geometry buffer of `count` items of `bytes` each; Embree gives null when it cannot.
template <typename T>
T* new_buffer(RTCGeometry g, RTCBufferType type, RTCFormat format, size_t bytes, size_t count) {
  void* b = rtcSetNewGeometryBuffer(g, type, 0, format, bytes, count);
  if (!b) throw std::runtime_error("Embree: cannot allocate a buffer of " +
                                   std::to_string(count) + " items");
  return static_cast<T*>(b);
}

// What a frame's picture holds, one layer per Embree geometry (its geomID): the particles as
// spheres, a triangle mesh (the particles' surface, or cloth), or tubes (yarn and hair).
enum class LayerKind { Spheres, Triangles, Tubes };
struct Layer {
  LayerKind kind = LayerKind::Spheres;
  const float* sphere = nullptr;     // spheres: x y z r each (Embree's buffer)
  std::vector<Vector3f> albedo;      // linear, per sphere or per vertex
  std::vector<Vector3f> vertices;    // triangles and tubes
  std::vector<Vector3f> normal;      // triangles, per vertex
  std::vector<std::array<int32_t, 3>> elements;  // triangles; tubes' segments use the first two
  std::vector<float> radius;         // tubes, per segment
  bool codim = false;                // a codimensional mesh part
};

// The closest t > 0 at which the ray o + t d (|d| = 1) meets the capsule of radius r round the
// segment a b, or a negative value when it misses.
double capsule_hit(const Vector3d& o, const Vector3d& d, const Vector3d& a, const Vector3d& b,
                   double r) {
  const Vector3d ba = b - a, oa = o - a;
  const double baba = ba.dot(ba), bard = ba.dot(d), baoa = ba.dot(oa), rdoa = d.dot(oa);
  const double A = baba - bard * bard, B = baba * rdoa - baoa * bard,
               C = baba * oa.dot(oa) - baoa * baoa - r * r * baba;
  if (A > 1e-12 * baba) {
    const double h = B * B - A * C;
    if (h < 0) return -1;
    const double t = (-B - std::sqrt(h)) / A, y = baoa + t * bard;
    if (y > 0 && y < baba) return t;
  }
  // The round caps: the sphere at the end the ray reaches first, then the other.
  double best = -1;
  for (const Vector3d* c : {&a, &b}) {
    const Vector3d oc = o - *c;
    const double q = d.dot(oc), h = q * q - (oc.dot(oc) - r * r);
    if (h < 0) continue;
    const double t = -q - std::sqrt(h);
    if (t > 0 && (best < 0 || t < best)) best = t;
  }
  return best;
}

// One frame's geometry in an Embree scene, and what shading needs to read back.
class Geometry {
 public:
  Geometry(RTCDevice device, const PointTable& frame, const std::vector<MeshPart>& meshes,
           const RenderLook& look, const RenderSettings& settings)
      : scene_(rtcNewScene(device)) {
    if (!scene_) throw std::runtime_error("Embree: cannot create a scene");
    rtcSetSceneBuildQuality(scene(), RTC_BUILD_QUALITY_MEDIUM);
    if (frame.count > 0) {
      const std::vector<Vector3f> albedo = point_albedo(frame, settings);
      std::vector<Vector3f> centre;
      centre.reserve(frame.count);
      for (const Vector3d& p : positions(frame)) centre.push_back(p.cast<float>());
      if (settings.surface)
        build_surface(device, frame, look, centre, albedo);
      else
        build_spheres(device, particle_radii(frame, look, settings), centre, albedo);
    }
    for (const MeshPart& part : meshes) build_part(device, part, settings);
    rtcCommitScene(scene());
  }
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;

  RTCScene scene() const { return scene_.get(); }

  // The closest surface along o + t d for t in (0, tmax); false when none.
  bool intersect(RTCIntersectContext* ctx, const Vector3d& o, const Vector3d& d, double tmax,
                 double* t, Surface* s) const {
    RTCRayHit rh;
    set_ray(&rh.ray, o, d, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene(), ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    const Layer& layer = layers_[rh.hit.geomID];
    const size_t k = rh.hit.primID;
    *t = rh.ray.tfar;
    s->codim = layer.codim;
    // Hits are re-solved in double from the primitive Embree found, so that shading depends
    // only on which primitive was hit.
    switch (layer.kind) {
      case LayerKind::Spheres: {
        const float* v = layer.sphere + 4 * k;
        const Vector3d c(v[0], v[1], v[2]);
        const double r = v[3];
        const Vector3d oc = o - c;
        const double b = oc.dot(d), disc = b * b - (oc.squaredNorm() - r * r);
        if (disc >= 0) {
          const double t0 = -b - std::sqrt(disc);
          *t = t0 > 0 ? t0 : -b + std::sqrt(disc);
        }
        s->p = o + *t * d;
        s->n = s->ng = (s->p - c).normalized();
        s->albedo = layer.albedo[k];
        break;
      }
      case LayerKind::Triangles: {
        const auto& tri = layer.elements[k];
        const Vector3d a = vertex(layer, tri[0]), e1 = vertex(layer, tri[1]) - a,
                       e2 = vertex(layer, tri[2]) - a;
        // Moller-Trumbore in double for t and the barycentrics.
        const Vector3d pv = d.cross(e2);
        const double det = e1.dot(pv);
        double u = rh.hit.u, w = rh.hit.v;
        if (std::abs(det) > 0) {
          const Vector3d tv = o - a, qv = tv.cross(e1);
          u = tv.dot(pv) / det;
          w = d.dot(qv) / det;
          *t = e2.dot(qv) / det;
        }
        s->p = o + *t * d;
        // A back face is seen inside a crack, through an open mesh or on cloth: light its
        // visible side.
        Vector3d ng = e1.cross(e2).normalized();
        const double side = ng.dot(d) > 0 ? -1 : 1;
        ng *= side;
        Vector3d n = (1 - u - w) * layer.normal[size_t(tri[0])].cast<double>() +
                     u * layer.normal[size_t(tri[1])].cast<double>() +
                     w * layer.normal[size_t(tri[2])].cast<double>();
        n *= side;
        // Interpolated normals bent away from the eye would light the wrong side.
        s->n = n.norm() > 0 && n.dot(d) < 0 ? Vector3d(n.normalized()) : ng;
        s->ng = ng;
        s->albedo = float(1 - u - w) * layer.albedo[size_t(tri[0])] +
                    float(u) * layer.albedo[size_t(tri[1])] +
                    float(w) * layer.albedo[size_t(tri[2])];
        break;
      }
      case LayerKind::Tubes: {
        const auto& seg = layer.elements[k];
        const Vector3d a = vertex(layer, seg[0]), b = vertex(layer, seg[1]);
        const double r = layer.radius[k];
        const double tc = capsule_hit(o, d, a, b, r);
        if (tc > 0) *t = tc;
        s->p = o + *t * d;
        const Vector3d ba = b - a;
        const double f =
            ba.squaredNorm() > 0 ? std::clamp((s->p - a).dot(ba) / ba.squaredNorm(), 0.0, 1.0) : 0;
        Vector3d n = s->p - (a + f * ba);
        if (!(n.norm() > 0)) n = -d;
        n.normalize();
        if (n.dot(d) > 0) n = -n;  // grazing: keep it towards the eye
        s->n = s->ng = n;
        s->albedo = float(1 - f) * layer.albedo[size_t(seg[0])] +
                    float(f) * layer.albedo[size_t(seg[1])];
        break;
      }
    }
    return true;
  }

  bool occluded(RTCIntersectContext* ctx, const Vector3d& o, const Vector3d& d, double tmax) const {
    RTCRay ray;
    set_ray(&ray, o, d, tmax);
    rtcOccluded1(scene(), ctx, &ray);
    return ray.tfar < 0;
  }

 private:
  static void set_ray(RTCRay* r, const Vector3d& o, const Vector3d& d, double tmax) {
    r->org_x = float(o.x()), r->org_y = float(o.y()), r->org_z = float(o.z());
    r->dir_x = float(d.x()), r->dir_y = float(d.y()), r->dir_z = float(d.z());
    r->tnear = 0;
    r->tfar = std::isfinite(tmax) ? float(tmax) : std::numeric_limits<float>::infinity();
    r->time = 0;
    r->mask = 0xffffffffu;
    r->id = 0;
    r->flags = 0;
  }

  static Vector3d vertex(const Layer& layer, int32_t i) {
    return layer.vertices[size_t(i)].cast<double>();
  }

  // Attaches a committed geometry as the next layer (its geomID is the layer's index).
  void attach(const GeometryHandle& g, Layer layer) {
    rtcCommitGeometry(g.get());
    rtcAttachGeometryByID(scene(), g.get(), unsigned(layers_.size()));
    layers_.push_back(std::move(layer));
  }

  void build_spheres(RTCDevice device, const std::vector<float>& radius,
                     const std::vector<Vector3f>& centre, const std::vector<Vector3f>& albedo) {
    std::vector<size_t> keep;
    keep.reserve(centre.size());
    for (size_t i = 0; i < centre.size(); ++i)
      if (centre[i].allFinite() && radius[i] > 0) keep.push_back(i);
    if (keep.empty()) return;
    const GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT));
    float* sphere = new_buffer<float>(g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4,
                                      4 * sizeof(float), keep.size());
    Layer layer;
    layer.kind = LayerKind::Spheres;
    layer.sphere = sphere;
    layer.albedo.resize(keep.size());
    for (size_t k = 0; k < keep.size(); ++k) {
      const size_t i = keep[k];
      float* v = sphere + 4 * k;
      v[0] = centre[i].x(), v[1] = centre[i].y(), v[2] = centre[i].z(), v[3] = radius[i];
      layer.albedo[k] = albedo[i];
    }
    attach(g, std::move(layer));
  }

  // A triangle layer of `layer`'s vertices and elements, with area-weighted vertex normals.
  void build_triangles(RTCDevice device, Layer layer) {
    if (layer.elements.empty()) return;
    layer.kind = LayerKind::Triangles;
    const std::vector<Vector3f>& x = layer.vertices;
    layer.normal.assign(x.size(), Vector3f::Zero());
    for (const auto& t : layer.elements) {
      const Vector3f n = (x[size_t(t[1])] - x[size_t(t[0])]).cross(x[size_t(t[2])] - x[size_t(t[0])]);
      for (int32_t i : t) layer.normal[size_t(i)] += n;  // area weighted
    }
    for (Vector3f& n : layer.normal)
      if (n.norm() > 0) n.normalize();
    const GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
    float* v = new_buffer<float>(g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3,
                                 3 * sizeof(float), x.size());
    for (size_t i = 0; i < x.size(); ++i)
      for (int a = 0; a < 3; ++a) v[3 * i + size_t(a)] = x[i][a];
    uint32_t* idx = new_buffer<uint32_t>(g.get(), RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3,
                                         3 * sizeof(uint32_t), layer.elements.size());
    for (size_t t = 0; t < layer.elements.size(); ++t)
      for (int a = 0; a < 3; ++a) idx[3 * t + size_t(a)] = uint32_t(layer.elements[t][size_t(a)]);
    attach(g, std::move(layer));
  }

  // A tube layer: each segment a round linear curve of its own (two vertices, no neighbours,
  // so both ends are capped by spheres: a capsule).
  void build_tubes(RTCDevice device, Layer layer) {
    if (layer.elements.empty()) return;
    layer.kind = LayerKind::Tubes;
    const size_t n = layer.elements.size();
    const GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE));
    float* v = new_buffer<float>(g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4,
                                 4 * sizeof(float), 2 * n);
    uint32_t* idx =
        new_buffer<uint32_t>(g.get(), RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT, sizeof(uint32_t), n);
    for (size_t s = 0; s < n; ++s) {
      for (int c = 0; c < 2; ++c) {
        const Vector3f& p = layer.vertices[size_t(layer.elements[s][size_t(c)])];
        float* q = v + 4 * (2 * s + size_t(c));
        q[0] = p.x(), q[1] = p.y(), q[2] = p.z(), q[3] = layer.radius[s];
      }
      idx[s] = uint32_t(2 * s);
    }
    attach(g, std::move(layer));
  }

  // A codimensional mesh part: cloth as two-sided triangles, yarn and hair as tubes of their
  // radius (the element column "radius", else settings.radius, else a hundredth of the part's
  // size); elements with a vertex that is not finite are left out.
  void build_part(RTCDevice device, const MeshPart& part, const RenderSettings& settings);

  void build_surface(RTCDevice device, const PointTable& frame, const RenderLook& look,
                     const std::vector<Vector3f>& centre, const std::vector<Vector3f>& albedo);

  SceneHandle scene_;
  std::vector<Layer> layers_;  // by geomID
};

// Colour of each mesh vertex: that of the nearest point, found in a hash grid of cells twice
// the particle spacing (searching outwards ring by ring).
std::vector<Vector3f> vertex_albedo(const std::vector<Vector3f>& vertices,
                                    const std::vector<Vector3f>& centre,
                                    const std::vector<Vector3f>& albedo, double spacing) {
  const double cell = 2 * std::max(spacing, 1e-12);
  auto key_of = [](int64_t i, int64_t j, int64_t k) {
    return uint64_t(i & 0x1fffff) | (uint64_t(j & 0x1fffff) << 21) | (uint64_t(k & 0x1fffff) << 42);
  };
  auto cell_of = [&](const Vector3f& p, int a) { return int64_t(std::floor(p[a] / cell)); };
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  for (size_t i = 0; i < centre.size(); ++i)
    if (centre[i].allFinite())
      grid[key_of(cell_of(centre[i], 0), cell_of(centre[i], 1), cell_of(centre[i], 2))].push_back(
          uint32_t(i));
  std::vector<Vector3f> out(vertices.size(), linear_rgb(Rgb(0.8f, 0.8f, 0.8f)));
  parallel_for(vertices.size(), [&](size_t v) {
    const Vector3f& p = vertices[v];
    const int64_t ci = cell_of(p, 0), cj = cell_of(p, 1), ck = cell_of(p, 2);
    float best = std::numeric_limits<float>::infinity();
    uint32_t best_i = 0;
    for (int ring = 1; ring <= 3 && !std::isfinite(best); ++ring)
      for (int64_t i = ci - ring; i <= ci + ring; ++i)
        for (int64_t j = cj - ring; j <= cj + ring; ++j)
          for (int64_t k = ck - ring; k <= ck + ring; ++k) {
            auto it = grid.find(key_of(i, j, k));
            if (it == grid.end()) continue;
            for (uint32_t q : it->second) {
              const float d2 = (centre[q] - p).squaredNorm();
              if (d2 < best || (d2 == best && q < best_i)) best = d2, best_i = q;
            }
          }
    if (!std::isfinite(best))  // far from every point (rare): look at all of them
      for (uint32_t q = 0; q < uint32_t(centre.size()); ++q) {
        const float d2 = (centre[q] - p).squaredNorm();
        if (d2 < best) best = d2, best_i = q;
      }
    if (std::isfinite(best)) out[v] = albedo[best_i];
  });
  return out;
}

void Geometry::build_surface(RTCDevice device, const PointTable& frame, const RenderLook& look,
                             const std::vector<Vector3f>& centre,
                             const std::vector<Vector3f>& albedo) {
  MeshOptions options;
  options.spacing = look.spacing;
  const TriMesh mesh = mesh_particles(frame, options);
  if (mesh.triangles.empty()) return;
  Layer layer;
  layer.vertices = mesh.vertices;
  layer.elements = mesh.triangles;
  layer.albedo = vertex_albedo(layer.vertices, centre, albedo, look.spacing);
  build_triangles(device, std::move(layer));
}

void Geometry::build_part(RTCDevice device, const MeshPart& part, const RenderSettings& settings) {
  const PointTable& t = part.vertices;
  Layer layer;
  layer.codim = true;
  for (const Vector3d& p : positions(t)) layer.vertices.push_back(p.cast<float>());
  layer.albedo = mesh_albedo(t, settings);
  const std::vector<double>* radius =
      part.element_columns.has("radius") ? &part.element_columns.column("radius") : nullptr;
  Vector3f lo = Vector3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
  for (const Vector3f& p : layer.vertices)
    if (p.allFinite()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const float fallback = float(0.01 * std::max(double((hi - lo).norm()), 1e-9));
  const int corners = part.corners == 2 ? 2 : 3;
  for (size_t e = 0; e < part.elements.size(); ++e) {
    std::array<int32_t, 3> el{0, 0, 0};
    bool ok = true;
    for (int c = 0; c < corners; ++c) {
      const uint32_t i = part.elements[e][size_t(c)];
      ok = ok && i < layer.vertices.size() && layer.vertices[i].allFinite();
      el[size_t(c)] = int32_t(i);
    }
    if (!ok) continue;
    layer.elements.push_back(el);
    if (corners == 2) {
      const double r = settings.radius > 0 ? settings.radius
                       : radius && e < radius->size() && (*radius)[e] > 0 ? (*radius)[e]
                                                                           : fallback;
      layer.radius.push_back(float(r));
    }
  }
  if (corners == 2)
    build_tubes(device, std::move(layer));
  else
    build_triangles(device, std::move(layer));
}

// Everything fixed while the pixels of one picture are traced.
struct Tracer {
  const Geometry& geo;
  const Stage& stage;
  int samples;
  CameraView view;
  Vector3d up, key;
  double cos_key, eps, ao_reach, mesh_gap;
  Vector3f top, bottom;  // background, linear
  std::optional<ColliderLayer> colliders;  // none: nothing to draw
  bool flat;                               // 2D: colliders lie over the particles

  Tracer(const Geometry& g, const Stage& st, const RenderLook& look, int n,
         const std::vector<Shape>& shapes)
      : geo(g), stage(st), samples(n), view(st.camera.view()), mesh_gap(look.mesh_gap),
        flat(look.dim == 2) {
    up = look.up.normalized();
    // Key light from above, in front of the body and to the left as the camera sees it.
    const Vector3d &forward = view.forward, &right = view.right;
    Vector3d back = -forward - (-forward).dot(up) * up, side = right - right.dot(up) * up;
    if (back.norm() < 1e-6) back = side.cross(up);
    if (side.norm() < 1e-6) side = up.cross(back);
    key = (up + 0.55 * back.normalized() - 0.5 * side.normalized()).normalized();
    cos_key = std::cos(kKeyConeDeg * M_PI / 180);
    eps = 1e-5 * st.size;
    ao_reach = kAoReach * st.size;
    top = linear_rgb(kBackgroundTop);
    bottom = linear_rgb(kBackgroundBottom);
    if (!shapes.empty()) {
      colliders.emplace(shapes, look.dim, view, up, st.ground, key, st.center, st.size);
      if (colliders->empty()) colliders.reset();
    }
  }

  Vector3f background(double fy) const {
    const float w = float(std::clamp(fy, 0.0, 1.0));
    return (1 - w) * top + w * bottom;
  }

  double sky(const Vector3d& w) const {
    const double e = w.dot(up);
    return e > 0 ? kSkyHorizon + (kSkyZenith - kSkyHorizon) * e : kBounce;
  }

  // Light reaching the eye from a surface point: key light with a soft shadow, plus the sky
  // over one cosine-weighted direction that is not occluded nearby.
  Vector3f shade(RTCIntersectContext* ctx, const Vector3d& p, const Vector3d& n, const Vector3d& ng,
                 const Vector3f& albedo, const Sampler& sm, int s) const {
    const Vector3d o = p + eps * ng;
    double light = 0;
    {
      const Eigen::Vector2d u = sm.get(s, 1);
      const double ct = 1 - u.x() * (1 - cos_key), st = std::sqrt(std::max(0.0, 1 - ct * ct));
      const double phi = 2 * M_PI * u.y();
      Vector3d t, b;
      tangents(key, &t, &b);
      const Vector3d l = ct * key + st * (std::cos(phi) * t + std::sin(phi) * b);
      const double ndl = n.dot(l);
      if (ndl > 0 && l.dot(ng) > 0 && !geo.occluded(ctx, o, l, kInf)) light += kKey * ndl;
    }
    {
      const Eigen::Vector2d u = sm.get(s, 2);
      const double r = std::sqrt(u.x()), phi = 2 * M_PI * u.y();
      Vector3d t, b;
      tangents(n, &t, &b);
      const Vector3d w =
          r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u.x())) * n;
      if (w.dot(ng) > 0 && !geo.occluded(ctx, o, w, ao_reach)) light += sky(w);
    }
    return albedo * float(light);
  }

  Vector3f trace(RTCIntersectContext* ctx, double px, double py, const Sampler& sm, int s) const {
    const Vector3d d = view.ray(px, py);
    const Vector3d& eye = view.eye;
    double t_ground = kInf;
    const double du = d.dot(up);
    if (du < 0) {
      const double t = (stage.ground - eye.dot(up)) / du;
      if (t > 0) t_ground = t;
    }
    double t;
    Surface hit;
    Vector3f c;
    double depth = t_ground;  // of what the ray sees
    if (geo.intersect(ctx, eye, d, t_ground, &t, &hit)) {
      c = shade(ctx, hit.p, hit.n, hit.ng, hit.albedo, sm, s);
      // Cloth and hair lie on a collider with their vertices, and their flat triangles and
      // straight segments cut into a round one between them: a collider less than mesh_gap
      // in front of them (along their normal: further along a grazing ray) is taken to be
      // under them.
      depth = hit.codim ? t - mesh_gap / std::max(std::abs(d.dot(hit.ng)), 0.2) : t;
    } else {
      c = background(py / stage.camera.height);
      if (std::isfinite(t_ground)) {
        // The ground, fading into the background with distance from the body.
        const Vector3d p = eye + t_ground * d;
        const Vector3f g =
            shade(ctx, p, up, up, Vector3f::Constant(srgb_to_linear(kGroundAlbedo)), sm, s);
        const float fog = float(distance_fade(p, stage.center, up, stage.size));
        c = fog * g + (1 - fog) * c;
      }
    }
    if (!colliders) return c;
    // In 2D the colliders lie over the particles: only the ground hides them.
    return colliders->over(d, flat ? t_ground : depth, c);
  }
};

}  // namespace

Image Renderer::render(const PointTable& frame, const RenderLook& look, const Stage& stage,
                       const RenderSettings& settings, const std::string& caption,
                       const std::vector<Shape>& colliders,
                       const std::vector<MeshPart>& meshes) const {
  Geometry geo(device_->device, frame, meshes, look, settings);
  device_->check();
  const int w = stage.camera.width, h = stage.camera.height, n = std::max(1, settings.samples);
  const Tracer tracer(geo, stage, look, n, colliders);
  Image image(w, h);
  parallel_for_tiles(h, w, 16, [&](int y0, int y1, int x0, int x1) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const Sampler sm{mix32(uint32_t(x) * 0x8da6b343u ^ mix32(uint32_t(y) * 0xd8163841u))};
        Vector3f sum = Vector3f::Zero();
        for (int s = 0; s < n; ++s) {
          const Eigen::Vector2d j = sm.get(s, 0);
          sum += tracer.trace(&ctx, x + j.x(), y + j.y(), sm, s);
        }
        sum /= float(n);
        uint8_t* p = image.at(x, y);
        for (int c = 0; c < 3; ++c) p[c] = uint8_t(std::lround(linear_to_srgb(sum[c]) * 255));
      }
  });
  device_->check();
  Legend legend;
  legend.color = settings.color;
  // Meshes without the map's columns are coloured by material: so is the legend when nothing
  // else is in the picture.
  bool map_shown = frame.count > 0;
  for (const MeshPart& part : meshes) map_shown = map_shown || part.vertices.has(map_column(settings.color));
  if (!map_shown && !meshes.empty()) legend.color = ColorBy::Material;
  legend.max = settings.range_max;
  legend.dim = look.dim;
  legend.material_names = look.material_names;
  if (legend.material_names.empty()) {
    double top = -1;
    if (frame.has("material"))
      for (double m : frame.column("material")) top = std::max(top, m);
    for (const MeshPart& part : meshes)
      if (part.vertices.has("material"))
        for (double m : part.vertices.column("material")) top = std::max(top, m);
    for (int i = 0; i <= int(top) && i < 256; ++i)
      legend.material_names.push_back(std::to_string(i));
  }
  draw_legend(&image, legend);
  draw_caption(&image, caption);
  return image;
}

}  // namespace tear
