// render/: the headless preview renderer behind `tear render` and `tear run --render`: frames
// (point tables) ray traced with Embree as spheres or as their surface mesh, lit by a soft key
// light and a sky with ambient occlusion over a ground plane, with a legend; PNG out, video via
// ffmpeg (video.h), and the colliders as translucent shapes (collider_layer.h). Knows point
// tables, meshes and shapes; knows nothing of scenes, grids or solvers.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tear/geometry/shape.h"
#include "tear/io/mesh_frames.h"
#include "tear/io/point_table.h"
#include "tear/render/camera.h"
#include "tear/render/image.h"

namespace tear {

// What the particles are coloured by: the frame columns damage, material, fx fy fz, vx vy vz,
// driving_force, damage_laplacian (the last two only where the run wrote them).
enum class ColorBy { Damage, Material, Fibers, Velocity, DrivingForce, DamageLaplacian };

// "damage", "material", "fibers", "velocity", "driving_force", "damage_laplacian".
const char* color_by_name(ColorBy c);
// The inverse; throws std::invalid_argument naming the choices.
ColorBy parse_color_by(const std::string& name);

// What the renderer knows about a run beyond its frames (the driver fills it from scene.json).
struct RenderLook {
  int dim = 3;
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  // unit; "above" for the ground and the camera
  bool falls = false;          // gravity acts: the camera also frames the ground below the body
  std::vector<double> floors;  // heights (along `up`) of planes the particles cannot pass
  std::vector<double> material_radius;      // sphere radius per material index
  double radius = 0.01;                     // sphere radius of other materials
  double spacing = 0.02;                    // particle spacing (surface mesher)
  // How far in front of a codimensional mesh a collider may be and still be drawn under it
  // (the grid spacing: meshes touch colliders at their vertices, and chords cut into curved
  // colliders between them).
  double mesh_gap = 0;
  std::vector<std::string> material_names;  // by material index, for the legend
};

struct RenderSettings {
  int width = 960, height = 540;
  int samples = 4;  // per pixel (antialiasing, soft shadow and ambient occlusion samples)
  ColorBy color = ColorBy::Damage;
  bool surface = false;  // trace the surface mesh (surface/mesher.h) instead of spheres
  double radius = 0;     // > 0: this sphere radius for every particle
  // Camera: unset parts are fitted to the first frame (fit_stage).
  std::optional<Eigen::Vector3d> camera_position, camera_target, camera_up;
  double fov_deg = 40;      // vertical field of view
  // Top of the velocity and driving-force maps, and the ends (-range_max, range_max) of the
  // damage Laplacian's (the driver fits it to the frames: color_range_top).
  double range_max = 1;
};

// The parts of a picture that stay fixed over a sequence: fitted to its first frame.
struct Stage {
  Camera camera;
  double ground = 0;  // height of the ground plane along RenderLook::up
  double size = 1;    // diagonal of the first frame's bounding box (sets fog and AO reach)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
};

// Fits the camera (unless the settings fix it) so that every particle of `first`, and every
// point of `also` (where later frames or the colliders reach), is inside the picture with a
// margin: 2D looks along -z at the plane, 3D from an elevated three-quarter view. The ground
// goes on the highest floor below all of it, else a little below its lowest point.
Stage fit_stage(const PointTable& first, const RenderLook& look, const RenderSettings& settings,
                const std::vector<Eigen::Vector3d>& also = {});

// The vertices of codimensional meshes, for fit_stage's `also`.
std::vector<Eigen::Vector3d> mesh_points(const std::vector<MeshPart>& meshes);

// Sphere radius of each point (settings.radius, else by material).
std::vector<float> particle_radii(const PointTable& frame, const RenderLook& look,
                                  const RenderSettings& settings);

// Ray traces frames. Owns the Embree device; one per sequence. Deterministic: the same input
// gives the same pixels for any thread count (each pixel's samples are seeded by its position).
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // One picture of `frame` with the legend of settings.color and `caption` (top left) drawn in,
  // `colliders` (shapes where they are at the frame's time) over it (collider_layer.h), and
  // the codimensional `meshes` (io/mesh_frames.h) beside the particles: cloth as shaded
  // two-sided triangles, yarn and hair as round tubes of their radius (the element column
  // "radius"; settings.radius, when set, for every tube), coloured by the map where their
  // vertices have its columns, else by material. Throws std::runtime_error when a column the
  // colour map needs is missing from the particles.
  Image render(const PointTable& frame, const RenderLook& look, const Stage& stage,
               const RenderSettings& settings, const std::string& caption = "",
               const std::vector<Shape>& colliders = {},
               const std::vector<MeshPart>& meshes = {}) const;

 private:
  struct Device;
  std::unique_ptr<Device> device_;
};

// The Embree version this build was compiled against (`tear info`).
const char* embree_version();

// Largest speed |(vx, vy, vz)| in a frame (0 without velocity columns).
double max_speed(const PointTable& frame);
// Whether the map `c` has a range fitted to the frames (velocity, driving force, damage
// Laplacian), RenderSettings::range_max.
bool has_range(ColorBy c);
// Where a frame puts the top of the colour map `c` (RenderSettings::range_max): the largest
// speed for velocity; for the driving force and |damage Laplacian|, the 99th percentile of the
// particles' values, so that a few extreme particles (next to a grip) do not wash out the rest.
// 0 for the other maps and without the columns.
double color_range_top(const PointTable& frame, ColorBy c);

}  // namespace tear
