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

// What a camera ray found.
struct Surface {
  Vector3d p;
  Vector3d n;   // shading normal, on the side of the eye
  Vector3d ng;  // geometric normal, on the side of the eye (where secondary rays start)
  Vector3f albedo;
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

// One frame's geometry in an Embree scene, and what shading needs to read back.
class Geometry {
 public:
  Geometry(RTCDevice device, const PointTable& frame, const RenderLook& look,
           const RenderSettings& settings)
      : scene_(rtcNewScene(device)) {
    if (!scene_) throw std::runtime_error("Embree: cannot create a scene");
    rtcSetSceneBuildQuality(scene(), RTC_BUILD_QUALITY_MEDIUM);
    const std::vector<Vector3f> albedo = point_albedo(frame, settings);
    std::vector<Vector3f> centre;
    centre.reserve(frame.count);
    for (const Vector3d& p : positions(frame)) centre.push_back(p.cast<float>());
    if (settings.surface)
      build_mesh(device, frame, look, centre, albedo);
    else
      build_spheres(device, particle_radii(frame, look, settings), centre, albedo);
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
    const size_t k = rh.hit.primID;
    if (spheres_) {
      // Re-solve the hit in double from the primitive Embree found, so shading depends only on
      // which sphere was hit.
      const float* v = sphere_ + 4 * k;
      const Vector3d c(v[0], v[1], v[2]);
      const double r = v[3];
      const Vector3d oc = o - c;
      const double b = oc.dot(d), disc = b * b - (oc.squaredNorm() - r * r);
      *t = rh.ray.tfar;
      if (disc >= 0) {
        const double t0 = -b - std::sqrt(disc);
        *t = t0 > 0 ? t0 : -b + std::sqrt(disc);
      }
      s->p = o + *t * d;
      s->n = s->ng = (s->p - c).normalized();
      s->albedo = albedo_[k];
    } else {
      const auto& tri = triangles_[k];
      const Vector3d a = vertex(tri[0]), e1 = vertex(tri[1]) - a, e2 = vertex(tri[2]) - a;
      // Moller-Trumbore in double for t and the barycentrics.
      const Vector3d pv = d.cross(e2);
      const double det = e1.dot(pv);
      double u = rh.hit.u, w = rh.hit.v;
      *t = rh.ray.tfar;
      if (std::abs(det) > 0) {
        const Vector3d tv = o - a, qv = tv.cross(e1);
        u = tv.dot(pv) / det;
        w = d.dot(qv) / det;
        *t = e2.dot(qv) / det;
      }
      s->p = o + *t * d;
      // A back face is seen inside a crack or through an open mesh: light its visible side.
      Vector3d ng = e1.cross(e2).normalized();
      const double side = ng.dot(d) > 0 ? -1 : 1;
      ng *= side;
      Vector3d n = (1 - u - w) * normal_[size_t(tri[0])].cast<double>() +
                   u * normal_[size_t(tri[1])].cast<double>() +
                   w * normal_[size_t(tri[2])].cast<double>();
      n *= side;
      // Interpolated normals bent away from the eye would light the wrong side.
      s->n = n.norm() > 0 && n.dot(d) < 0 ? Vector3d(n.normalized()) : ng;
      s->ng = ng;
      s->albedo = float(1 - u - w) * albedo_[size_t(tri[0])] + float(u) * albedo_[size_t(tri[1])] +
                  float(w) * albedo_[size_t(tri[2])];
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

  Vector3d vertex(int32_t i) const { return vertices_[size_t(i)].cast<double>(); }

  void build_spheres(RTCDevice device, const std::vector<float>& radius,
                     const std::vector<Vector3f>& centre, const std::vector<Vector3f>& albedo) {
    spheres_ = true;
    std::vector<size_t> keep;
    keep.reserve(centre.size());
    for (size_t i = 0; i < centre.size(); ++i)
      if (centre[i].allFinite() && radius[i] > 0) keep.push_back(i);
    if (keep.empty()) return;
    const GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT));
    sphere_ = new_buffer<float>(g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4,
                                4 * sizeof(float), keep.size());
    albedo_.resize(keep.size());
    for (size_t k = 0; k < keep.size(); ++k) {
      const size_t i = keep[k];
      float* v = sphere_ + 4 * k;
      v[0] = centre[i].x(), v[1] = centre[i].y(), v[2] = centre[i].z(), v[3] = radius[i];
      albedo_[k] = albedo[i];
    }
    rtcCommitGeometry(g.get());
    rtcAttachGeometry(scene(), g.get());
  }

  void build_mesh(RTCDevice device, const PointTable& frame, const RenderLook& look,
                  const std::vector<Vector3f>& centre, const std::vector<Vector3f>& albedo);

  SceneHandle scene_;
  bool spheres_ = true;
  float* sphere_ = nullptr;         // x y z r per sphere (Embree's buffer)
  std::vector<Vector3f> albedo_;    // linear, per sphere or per mesh vertex
  std::vector<Vector3f> vertices_;  // mesh
  std::vector<Vector3f> normal_;    // mesh, per vertex
  std::vector<std::array<int32_t, 3>> triangles_;
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

void Geometry::build_mesh(RTCDevice device, const PointTable& frame, const RenderLook& look,
                          const std::vector<Vector3f>& centre,
                          const std::vector<Vector3f>& albedo) {
  spheres_ = false;
  MeshOptions options;
  options.spacing = look.spacing;
  const TriMesh mesh = mesh_particles(frame, options);
  vertices_ = mesh.vertices;
  triangles_ = mesh.triangles;
  if (triangles_.empty()) return;
  albedo_ = vertex_albedo(vertices_, centre, albedo, look.spacing);
  normal_.assign(vertices_.size(), Vector3f::Zero());
  for (const auto& t : triangles_) {
    const Vector3f n = (vertices_[size_t(t[1])] - vertices_[size_t(t[0])])
                           .cross(vertices_[size_t(t[2])] - vertices_[size_t(t[0])]);
    for (int32_t i : t) normal_[size_t(i)] += n;  // area weighted
  }
  for (Vector3f& n : normal_)
    if (n.norm() > 0) n.normalize();
  const GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
  float* v = new_buffer<float>(g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3,
                               3 * sizeof(float), vertices_.size());
  for (size_t i = 0; i < vertices_.size(); ++i)
    for (int a = 0; a < 3; ++a) v[3 * i + size_t(a)] = vertices_[i][a];
  uint32_t* idx = new_buffer<uint32_t>(g.get(), RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3,
                                       3 * sizeof(uint32_t), triangles_.size());
  for (size_t t = 0; t < triangles_.size(); ++t)
    for (int a = 0; a < 3; ++a) idx[3 * t + size_t(a)] = uint32_t(triangles_[t][size_t(a)]);
  rtcCommitGeometry(g.get());
  rtcAttachGeometry(scene(), g.get());
}

// Everything fixed while the pixels of one picture are traced.
struct Tracer {
  const Geometry& geo;
  const Stage& stage;
  int samples;
  CameraView view;
  Vector3d up, key;
  double cos_key, eps, ao_reach;
  Vector3f top, bottom;  // background, linear
  std::optional<ColliderLayer> colliders;  // none: nothing to draw
  bool flat;                               // 2D: colliders lie over the particles

  Tracer(const Geometry& g, const Stage& st, const RenderLook& look, int n,
         const std::vector<Shape>& shapes)
      : geo(g), stage(st), samples(n), view(st.camera.view()), flat(look.dim == 2) {
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
      depth = t;
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
                       const std::vector<Shape>& colliders) const {
  Geometry geo(device_->device, frame, look, settings);
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
  legend.max = settings.range_max;
  legend.dim = look.dim;
  legend.material_names = look.material_names;
  if (legend.material_names.empty() && frame.has("material")) {
    double top = -1;
    for (double m : frame.column("material")) top = std::max(top, m);
    for (int i = 0; i <= int(top) && i < 256; ++i)
      legend.material_names.push_back(std::to_string(i));
  }
  draw_legend(&image, legend);
  draw_caption(&image, caption);
  return image;
}

}  // namespace tear
