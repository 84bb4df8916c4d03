// scene/: loading, validating and resolving JSON scene files (../shared/design/SCENE_FORMAT.md).
// Owns Scene (a plain description) and SceneError, and turns a scene into the core's plain
// settings (mpm_settings); shapes come from geometry/, colliders from grid/. Never runs anything.
#pragma once

#include "tear/damage/damage_settings.h"
#include "tear/fem/mesh.h"
#include "tear/geometry/codim_mesh.h"
#include "tear/geometry/shape.h"
#include "tear/grid/collider.h"
#include "tear/materials/material.h"
#include "tear/mpm/settings.h"

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <memory>
#include <string>
#include <vector>

namespace tear {

// The one error type of the scene layer. what() is "FILE: JSON.PATH: reason".
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, const std::string& path, const std::string& reason);
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, path_, reason_;
};

// In the scene's order of names. Flow: the directions of a potential flow from sources to
// sinks (scene/flow_fibers.h); FromFile takes each point's fibers from a "particles" object's
// file.
enum class FiberField { Constant, Radial, Circumferential, Longitudinal, Random, Flow, FromFile };

struct FiberSpec {
  FiberField type = FiberField::Constant;
  Vec3d a1 = Vec3d::UnitX();
  Vec3d a2 = Vec3d::Zero();     // zero: choose any unit vector orthogonal to a1
  bool has_a2 = false;
  Vec3d center = Vec3d::Zero(); // radial / circumferential / longitudinal reference point
  Vec3d axis = Vec3d::UnitZ();  // circumferential / longitudinal axis (3D; 2D uses z)
  // flow (scene/flow_fibers.h): where the flow enters and leaves, and how near a cell must be
  // to be held (0: two grid cells). a1 is the direction where the flow does not reach.
  std::vector<Vec3d> sources, sinks;
  double flow_radius = 0;
  // > 0: each particle's a1 turned by a random angle up to this many degrees (2D: uniform in
  // [-spread, spread]; 3D: uniform in [0, spread] towards a random perpendicular direction).
  double spread = 0;
};

struct MaterialSpec {
  std::string name;
  // The codimensional keys (normal_stiffness, shear_stiffness, friction) are in params.
  MaterialParams params;
  Real fiber_scale[2] = {0, 0};
  DamageParams damage;
  PlasticParams plasticity;  // YieldSurface::None: elastic
  InextensibleParams inextensibility;  // keys inextensible, inextensibility_relaxation
  // Key rayleigh {"alpha": 1/s, "beta": s}: the damping force -(alpha M + beta K) v of FEM
  // bodies (docs/fem.md); 0, 0: none.
  double rayleigh_alpha = 0, rayleigh_beta = 0;
};

// The points of a "particles" object, read from its PLY file: positions, and whatever else the
// file has (empty: not in the file).
struct PointSet {
  std::vector<Vec3d> x;
  std::vector<Vec3d> v;         // vx vy [vz]
  std::vector<double> volume;   // volume (rest volume of each particle)
  std::vector<int> material;    // material (index in name order)
  std::vector<Vec3d> a1, a2;    // fx fy [fz], f2x f2y [f2z]
};

// A region of an object: where the region's shape contains a particle of the object (and no
// earlier region does), the particle gets the region's material and fibers.
struct RegionSpec {
  Shape shape;
  int material = 0;  // index into Scene::materials
  FiberSpec fibers;
};

// What an object is (its "kind"): a solid sampled with particles, or a codimensional body of
// Jiang et al. 2017 whose mesh becomes particles: a surface (cloth, 3D) or curves (yarn, hair).
enum class ObjectKind { Volume, Surface, Curves };

struct ObjectSpec {
  ObjectKind kind = ObjectKind::Volume;
  // Surface and curves objects: the world-space mesh (checked: no degenerate element, every
  // vertex inside the domain less one cell), a surface's thickness and a curve's radius.
  std::shared_ptr<const CodimMesh> mesh;
  double thickness = 0, radius = 0;
  Shape shape;
  int material = 0;            // index into Scene::materials
  int ppc = 4;                 // particles per cell
  bool grid_sampling = false;  // "sampling": "grid" (regular lattice) vs stratified random
  Vec3d velocity = Vec3d::Zero();
  Vec3d angular_velocity = Vec3d::Zero();  // about the shape's world centre; 2D uses z
  FiberSpec fibers;  // surfaces: a constant a1 is the warp direction
  std::vector<RegionSpec> regions;  // in priority order; particles in none keep the above
  // A "particles" object: its points (not sampled); `shape` is then their bounding box.
  std::shared_ptr<const PointSet> points;
  // "simulation": "fem": the body is a tetrahedral (triangle) mesh of the shape with edges of
  // about mesh_size (default grid.dx), simulated by fem/ (docs/fem.md), not sampled.
  bool fem = false;
  double mesh_size = 0;
  // An FEM body whose shape is a volume mesh file (a "mesh" shape of .msh, .node/.ele or .vtu):
  // its elements as they are (checked), nodes in world space; mesh_size is then their mean edge.
  // Null: netgen meshes the shape.
  std::shared_ptr<const FemMesh> fem_mesh;
  // "initial_nodes": where an FEM body's nodes start (its rest shape is the mesh's): at rest, each
  // at a random point of the mesh's bounding box, or all at the shape's centre, each within a
  // thousandth of mesh_size of it (AnisoMPM Fig. 19; docs/fem.md says why not exactly there).
  enum class NodeStart { Rest, Random, Point };
  NodeStart node_start = NodeStart::Rest;
  // "mass": "consistent": the elements' consistent mass matrices in the implicit integrator's
  // inertia instead of lumped masses (docs/fem.md).
  bool consistent_mass = false;
};

// Preview rendering defaults ("render" section) for `tear render` and `tear run --render`;
// their command-line options override these. Camera vectors are 3D in 2D scenes too.
struct RenderSpec {
  // The colour maps and the bounds on the picture that the scene and the command line share.
  static constexpr const char* kColors[] = {"damage",   "material",      "fibers",
                                            "velocity", "driving_force", "damage_laplacian"};
  static constexpr int kMinSize = 16, kMaxSize = 16384, kMaxSamples = 1024;

  std::string color = "damage";  // one of kColors
  int width = 960, height = 540;
  int samples = 4;  // per pixel
  bool surface = false;
  bool has_position = false, has_target = false, has_up = false;  // unset: fitted
  Vec3d position = Vec3d::Zero(), target = Vec3d::Zero(), up = Vec3d::UnitY();
  double fov_deg = 40;  // vertical
};

struct Scene {
  std::string file;  // path the scene was loaded from ("" when built in code)
  std::string name;
  std::string description;  // free text, lines joined by "\n"
  int dim = 2;
  uint64_t seed = 1;
  // grid
  double dx = 0.01;
  Vec3d domain_min = Vec3d::Zero(), domain_max = Vec3d::Ones();
  ContactType walls = ContactType::Separate;
  // time
  double frame_dt = 1.0 / 24;
  int frames = 24;
  double cfl = 0.4;
  double max_dt = 1e-3;
  Vec3d gravity = Vec3d::Zero();
  Transfer transfer = Transfer::Apic;
  Integrator integrator = Integrator::Explicit;
  NewtonSettings newton;  // scene key `implicit`
  ImplicitPreconditioner implicit_preconditioner = ImplicitPreconditioner::Auto;  // `implicit.preconditioner`
  InextensibilitySettings inextensibility;  // scene key `inextensibility`
  double flip_ratio = 0.95;
  // > 0: FLIP's per-step ratio is exp(-dt / flip_relaxation_time) instead of flip_ratio, so
  // particle velocities relax to the grid's at a rate that does not depend on the step.
  double flip_relaxation_time = 0;
  DamageSettings damage;
  std::vector<MaterialSpec> materials;
  std::vector<ObjectSpec> objects;
  std::vector<Collider> boundaries;
  // output
  int output_every = 1;
  std::vector<std::string> formats{"ply"};
  // The formats of the codimensional meshes' files (io/mesh_frames.h): ply, obj, vtu.
  std::vector<std::string> mesh_formats{"ply"};
  int checkpoint_every = 10;
  // Optional frame columns to write (Particles::optional_columns()): driving_force,
  // damage_laplacian.
  std::vector<std::string> output_fields;
  RenderSpec render;

  nlohmann::json resolved;  // the full scene with every default filled in
};

// Load, validate and resolve a scene. `overrides` are "dotted.path=VALUE" strings from
// `tear run --set`; VALUE is parsed as JSON when it parses, else taken as a string.
// Throws SceneError naming the file, the JSON path and the reason.
// `resolution` K refines the grid: grid.dx and time.max_dt are divided by K after the
// overrides (tear run --resolution).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                 double resolution = 1);
// Same, from the JSON text of a scene file at `path` (named in errors; mesh and particle files
// are relative to its folder); load_scene reads the file and calls this.
Scene load_scene_text(const std::string& text, const std::string& path,
                      const std::vector<std::string>& overrides = {}, double resolution = 1);
// Same, from an in-memory JSON document (`file` is used in error messages and to resolve paths).
Scene parse_scene(const nlohmann::json& doc, const std::string& file);

// The solver's settings of a scene: everything the MPM core needs, nothing of files, outputs or
// pictures. A damage solver of "none" disables every material's damage.
MpmSettings mpm_settings(const Scene& scene);

// An object's particles per cell when its "ppc" is omitted: 4 in 2D, 8 in 3D.
int default_ppc(int dim);
// The spacing of particles sampled `ppc` per cell, dx / ppc^(1/dim); with no `ppc` (0), that of
// the scene's densest object, the finest spacing a run starts with.
double particle_spacing(const Scene& s, int ppc = 0);

}  // namespace tear
