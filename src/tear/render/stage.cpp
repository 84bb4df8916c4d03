// Fitting the fixed parts of a sequence (camera, ground) to its first frame, and the per-point
// quantities the renderer reads from a frame.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tear/render/render.h"

namespace tear {

using Eigen::Vector3d;

namespace {

// Fraction of the half-width / half-height kept free at the picture's edges (the legend sits
// in the right-hand one).
constexpr double kMarginX = 0.16, kMarginY = 0.12;
// The elevated three-quarter view of 3D scenes: elevation above the ground and azimuth from
// the "front" axis towards the "right" axis.
constexpr double kElevationDeg = 25, kAzimuthDeg = 35;

// A horizontal unit vector (orthogonal to `up`), preferring +z, then +x, then +y: the side the
// default 3D camera looks from.
Vector3d front_of(const Vector3d& up) {
  for (const Vector3d& axis :
       {Vector3d(Vector3d::UnitZ()), Vector3d(Vector3d::UnitX()), Vector3d(Vector3d::UnitY())}) {
    const Vector3d f = axis - axis.dot(up) * up;
    if (f.norm() > 0.3) return f.normalized();
  }
  return Vector3d::UnitZ();
}

}  // namespace

const char* color_by_name(ColorBy c) {
  switch (c) {
    case ColorBy::Damage: return "damage";
    case ColorBy::Material: return "material";
    case ColorBy::Fibers: return "fibers";
    case ColorBy::Velocity: return "velocity";
    case ColorBy::DrivingForce: return "driving_force";
    case ColorBy::DamageLaplacian: return "damage_laplacian";
  }
  return "damage";
}

ColorBy parse_color_by(const std::string& name) {
  std::string names;
  for (ColorBy c : {ColorBy::Damage, ColorBy::Material, ColorBy::Fibers, ColorBy::Velocity,
                    ColorBy::DrivingForce, ColorBy::DamageLaplacian}) {
    if (name == color_by_name(c)) return c;
    names += std::string(names.empty() ? "" : ", ") + color_by_name(c);
  }
  throw std::invalid_argument("unknown colour map \"" + name + "\" (expected one of: " + names +
                              ")");
}

std::vector<float> particle_radii(const PointTable& frame, const RenderLook& look,
                                  const RenderSettings& settings) {
  std::vector<float> r(frame.count, float(settings.radius > 0 ? settings.radius : look.radius));
  if (settings.radius > 0 || !frame.has("material")) return r;
  const std::vector<double>& m = frame.column("material");
  for (size_t i = 0; i < frame.count; ++i) {
    const double k = m[i];
    if (k >= 0 && k < double(look.material_radius.size()))
      r[i] = float(look.material_radius[size_t(k)]);
  }
  return r;
}

std::vector<Vector3d> mesh_points(const std::vector<MeshPart>& meshes) {
  std::vector<Vector3d> out;
  for (const MeshPart& part : meshes)
    for (const Vector3d& p : positions(part.vertices))
      out.push_back(p.cast<float>().cast<double>());  // stored precision, as fit_stage's points
  return out;
}

double max_speed(const PointTable& frame) {
  if (!frame.has("vx")) return 0;
  const std::vector<double>* v[3] = {&frame.column("vx"),
                                     frame.has("vy") ? &frame.column("vy") : nullptr,
                                     frame.has("vz") ? &frame.column("vz") : nullptr};
  double best = 0;
  for (size_t i = 0; i < frame.count; ++i) {
    double s2 = 0;
    for (const std::vector<double>* c : v)
      if (c) s2 += double(float((*c)[i])) * double(float((*c)[i]));
    if (std::isfinite(s2)) best = std::max(best, std::sqrt(s2));
  }
  return best;
}

bool has_range(ColorBy c) {
  return c == ColorBy::Velocity || c == ColorBy::DrivingForce || c == ColorBy::DamageLaplacian;
}

double color_range_top(const PointTable& frame, ColorBy c) {
  if (c == ColorBy::Velocity) return max_speed(frame);
  // The other maps with a range are named after their frame column.
  const char* name = color_by_name(c);
  if (!has_range(c) || !frame.has(name) || frame.count == 0) return 0;
  // Stored precision (float), as for the speeds: a frame gives the same from memory and file.
  std::vector<double> size;
  size.reserve(frame.count);
  for (double v : frame.column(name))
    if (std::isfinite(float(v))) size.push_back(std::abs(double(float(v))));
  if (size.empty()) return 0;
  const size_t k = size_t(0.99 * double(size.size() - 1));
  std::nth_element(size.begin(), size.begin() + long(k), size.end());
  return size[k];
}

Stage fit_stage(const PointTable& first, const RenderLook& look, const RenderSettings& settings,
                const std::vector<Vector3d>& also) {
  const Vector3d up = look.up.normalized();
  const std::vector<float> radius = particle_radii(first, look, settings);
  // Points (with their radius) the picture must hold.
  std::vector<std::pair<Vector3d, double>> points;
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double low = std::numeric_limits<double>::infinity();
  const std::vector<Vector3d> centre = positions(first);
  points.reserve(centre.size());
  for (size_t i = 0; i < centre.size(); ++i) {
    // The stored (float) precision, so that a frame renders the same from memory and file.
    const Vector3d p = centre[i].cast<float>().cast<double>();
    if (!p.allFinite()) continue;
    const double r = radius[i];
    points.push_back({p, r});
    lo = lo.cwiseMin(p - Vector3d::Constant(r));
    hi = hi.cwiseMax(p + Vector3d::Constant(r));
    low = std::min(low, p.dot(up) - r);
  }
  for (const Vector3d& p : also) {
    if (!p.allFinite()) continue;
    points.push_back({p, 0});
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    low = std::min(low, p.dot(up));
  }
  Stage stage;
  if (points.empty()) {  // nothing to frame: a unit box at the origin
    lo = Vector3d::Constant(-0.5), hi = Vector3d::Constant(0.5);
    low = lo.dot(up);
    points.push_back({Vector3d::Zero(), 0.5});
  }
  stage.size = std::max((hi - lo).norm(), 1e-12);
  // The ground: the highest floor at or below the body, else a little below it.
  double ground = -std::numeric_limits<double>::infinity();
  for (double f : look.floors)
    if (f <= low + 1e-9 * stage.size) ground = std::max(ground, f);
  const bool on_floor = std::isfinite(ground);
  if (!on_floor) ground = low - 0.1 * stage.size;
  stage.ground = ground;
  // A falling body will land on the floor: frame the floor under it too (when it is near).
  if (look.falls && on_floor && low - ground <= 2 * stage.size) {
    for (int c = 0; c < 8; ++c) {
      const Vector3d corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                            (c & 4) ? hi.z() : lo.z());
      const Vector3d q = corner - (corner.dot(up) - ground) * up;
      points.push_back({q, 0});
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  stage.center = 0.5 * (lo + hi);

  Camera& cam = stage.camera;
  cam.width = settings.width;
  cam.height = settings.height;
  cam.fov_deg = settings.fov_deg;
  cam.up = settings.camera_up ? settings.camera_up->normalized() : up;
  cam.target = settings.camera_target ? *settings.camera_target : stage.center;
  if (settings.camera_position) {
    cam.position = *settings.camera_position;
    Vector3d r, u, f;
    cam.basis(&r, &u, &f);  // throws for a degenerate camera
    return stage;
  }
  // Direction from the target towards the camera.
  Vector3d back;
  if (look.dim == 2) {
    back = Vector3d::UnitZ();
  } else {
    const Vector3d front = front_of(up), right = up.cross(front);
    const double el = kElevationDeg * M_PI / 180, az = kAzimuthDeg * M_PI / 180;
    back = (std::cos(el) * (std::cos(az) * front + std::sin(az) * right) + std::sin(el) * up)
               .normalized();
  }
  cam.position = cam.target + back;
  Vector3d right, up_cam, forward;
  cam.basis(&right, &up_cam, &forward);
  // Smallest distance along `back` at which every point's sphere projects inside the margins:
  // lateral extent (|x| + r) over the nearest depth (D - z - r) within tan(half angle).
  const double ty = std::tan(0.5 * cam.fov_deg * M_PI / 180) * (1 - kMarginY);
  const double tx = std::tan(0.5 * cam.fov_deg * M_PI / 180) * double(cam.width) /
                    double(cam.height) * (1 - kMarginX);
  double distance = 0;
  for (const auto& [p, r] : points) {
    const Vector3d rel = p - cam.target;
    const double z = rel.dot(back) + r;
    const double need =
        std::max((std::abs(rel.dot(right)) + r) / tx, (std::abs(rel.dot(up_cam)) + r) / ty);
    distance = std::max(distance, z + std::max(need, 1e-6 * stage.size));
  }
  cam.position = cam.target + distance * back;
  return stage;
}

}  // namespace tear
