// driver/: the one interface through which the driver runs a simulation (MPM today, FEM later):
// stepping to frame times, per-frame statistics, the frame table from the field registry, and
// checkpoints. Each kind of simulation implements it over its own core module (mpm/, later
// fem/), with io/ for tables and checkpoint records.
#pragma once

#include "tear/fem/mesh.h"
#include "tear/io/binary.h"
#include "tear/io/mesh_frames.h"
#include "tear/io/point_table.h"
#include "tear/mpm/time_step.h"
#include "tear/scene/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tear {

// Figures of one frame, as written to stats.jsonl (ARCHITECTURE.md "Outputs").
struct FrameStats {
  int frame = 0;
  double time = 0;
  long steps = 0;  // steps taken since the previous frame
  double dt_min = 0, dt_max = 0;
  long steps_redone = 0;  // of those steps, the ones redone with a smaller dt (mpm/time_step.h)
  size_t particles = 0;
  double mass = 0;
  Vec3d momentum = Vec3d::Zero();
  Vec3d angular_momentum = Vec3d::Zero();  // about the origin, including the APIC affine part
  double kinetic_energy = 0, elastic_energy = 0;
  double max_damage = 0, mean_damage = 0, damaged_fraction = 0;
  // Implicit damage only (written when solver_figures): solves since the previous frame, their
  // sweeps summed and at most, solves that stopped at damage.max_iterations, and the largest
  // change of a particle's damage in a solve's last sweep.
  bool solver_figures = false;
  long damage_solves = 0, damage_iterations = 0, damage_unconverged = 0;
  int damage_iterations_max = 0;
  double damage_change = 0;
  // The implicit integrator only (written when implicit_figures): Newton iterations since the
  // previous frame summed and at most per step, CG iterations summed, the largest final
  // residual, the steps whose Newton solve stopped at implicit.max_iterations, and the Newton
  // iterations whose linear solve used multigrid (implicit.preconditioner).
  bool implicit_figures = false;
  long newton_iterations = 0, cg_iterations = 0, newton_unconverged = 0, cg_multigrid_solves = 0;
  int newton_iterations_max = 0;
  double newton_residual = 0;
  // Inextensible materials only (written when inextensibility_figures): CG iterations of the
  // projections since the previous frame summed and at most per step, the largest final
  // residual and the steps whose solve stopped at inextensibility.max_iterations.
  bool inextensibility_figures = false;
  long inextensibility_iterations = 0, inextensibility_unconverged = 0;
  int inextensibility_iterations_max = 0;
  double inextensibility_residual = 0;
  double wall_s = 0;  // wall time since the start of the run
  nlohmann::json to_json() const;
};

// Thrown by Simulation::step when a particle's position or velocity is no longer finite or a
// particle left the domain: the message names the frame, the step, the particle's id, material,
// position and velocity, and what to change.
class UnstableRun : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Simulation {
 public:
  virtual ~Simulation() = default;
  virtual int dim() const = 0;
  virtual size_t num_particles() const = 0;
  virtual int frame() const = 0;  // frames completed (0 = initial state)
  virtual double time() const = 0;
  virtual long total_steps() const = 0;
  // Advance to the next frame time, landing on it exactly, and return true; or, once `*stop`
  // (if given) is set, return false after the step in progress: a checkpoint written then
  // resumes mid-frame bit-identically.
  virtual bool advance_frame(const std::atomic<bool>* stop = nullptr) = 0;
  // Advance by exactly one step (no larger than `dt_cap`); returns the dt taken. Throws
  // UnstableRun if the step left a particle non-finite or outside the domain.
  virtual double step(double dt_cap) = 0;
  // Stable time step estimate for the current state, and what limits it.
  virtual double estimate_dt() const = 0;
  virtual DtLimits dt_limits() const = 0;
  // Statistics of the current state; step figures are those since the last call.
  virtual FrameStats collect_stats() = 0;
  // The current particles as the frame files' columns (ARCHITECTURE.md "Outputs"), rows in id
  // order, made a chunk at a time as an encoder reads them (io/frames.h encodes them in each
  // output format). Valid until the state changes or the next call.
  virtual PointRows frame_rows() const = 0;
  // The same rows as a whole table (for the renderer and checks). Valid until the next call
  // (the simulation reuses its storage from frame to frame).
  virtual const PointTable& frame_table() const = 0;
  // The codimensional parts of the frame (io/mesh_frames.h): one per kind of mesh the state
  // holds ("curves", "surfaces"), none for a state of solids only.
  virtual std::vector<MeshPart> frame_meshes() const { return {}; }
  // The figures of each FEM body's mesh (node and element counts, quality, the smallest height),
  // in object order; none for MPM.
  virtual std::vector<MeshFigures> body_meshes() const { return {}; }
  // Wall seconds spent so far in each phase of the step, in step order (for people).
  virtual std::vector<std::pair<std::string, double>> phase_seconds() const = 0;
  // Bytes of memory now held by particles and grid.
  virtual size_t memory_bytes() const = 0;
  // Restartable state: particles in their current order, time, frame and step counters.
  // A run resumed from it continues bit-identically to one that never stopped. The particle
  // fields are referenced where they are (no copy of the state): use the bytes before the
  // simulation changes.
  virtual ByteWriter checkpoint() const = 0;
  // The size of the largest checkpoint of this state's fields: one where no field holds the same
  // value for every particle (checkpoint() writes such a field once).
  virtual size_t checkpoint_bytes_max() const = 0;
  // The same bytes in one string.
  std::string encode_checkpoint() const { return checkpoint().bytes(); }
  // Throws std::runtime_error with the reason if the bytes are not a checkpoint of this scene
  // (format, dimension, particle count, fields).
  virtual void decode_checkpoint(const std::string& bytes) = 0;
};

// What every Simulation implementation shares (driver/simulation.cpp).
//
// The steps since the last statistics and their shortest and longest dt: FrameStats' step
// figures, and part of a checkpoint.
struct StepFigures {
  long steps = 0;
  double dt_min = std::numeric_limits<double>::infinity(), dt_max = 0;
  void add(double dt) {
    ++steps;
    dt_min = std::min(dt_min, dt);
    dt_max = std::max(dt_max, dt);
  }
  // Into `s` (steps, dt_min, dt_max; 0 without steps), then reset.
  void take(FrameStats* s);
  void write(ByteWriter* w) const;
  void read(ByteReader* r);
};

// Steps of sim.estimate_dt() until *time reaches `target`: the step that would cross it is
// shortened to land on it exactly (*time is set to target when that step was not cut shorter
// still). Returns false, after the step in progress, once `*stop` is set.
bool advance_to(Simulation& sim, double target, const std::atomic<bool>* stop, double* time);

// The checkpoint `bytes` opened after its magic (of `magic.size()` characters, the last its
// format version; `versions` the version characters this build reads), its checksum checked and
// its dimension and precision compared with this build's: a reader of the header that follows.
// Throws std::runtime_error: "not a tear checkpoint" (`not_ours` where the magic differs),
// another version, a damaged checksum, another dimension or precision.
ByteReader open_checkpoint(const std::string& bytes, const std::string& magic,
                           const std::string& versions, int dim, const std::string& not_ours);

// The simulation a scene describes: FEM where its objects are "simulation": "fem" bodies
// (driver/fem_simulation.cpp, their meshes made), else MPM (driver/mpm_simulation.cpp, its
// particles sampled from the scene).
std::unique_ptr<Simulation> make_simulation(const Scene& scene);
std::unique_ptr<Simulation> make_mpm_simulation(const Scene& scene);
std::unique_ptr<Simulation> make_fem_simulation(const Scene& scene);

}  // namespace tear
