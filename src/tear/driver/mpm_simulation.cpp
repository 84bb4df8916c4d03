// The MPM simulation behind the driver: settings and particles from the scene, the explicit
// integrator, frame tables and checkpoints from the particle field registry.
#include "tear/driver/simulation.h"
#include "tear/exec/domain.h"
#include "tear/exec/memory.h"
#include "tear/io/binary.h"
#include "tear/io/field_io.h"
#include "tear/mpm/explicit_step.h"
#include "tear/mpm/implicit_step.h"
#include "tear/mpm/measure.h"
#include "tear/scene/sampling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace tear {

namespace {

// Checkpoint format: this magic (its digit is the format's version), then the header below,
// then each group's state fields as io/field_io.h writes them, then a 64-bit checksum of
// everything before it (io/binary.h).
const std::string kCheckpointMagic = "TEARCKPB";

template <int Dim>
class MpmSimulation final : public Simulation {
 public:
  explicit MpmSimulation(const Scene& scene)
      : settings_(mpm_settings(scene)),
        frame_dt_(scene.frame_dt),
        state_(make_mpm_state<Dim>(settings_, sample_scene_groups<Dim>(scene))),
        start_(std::chrono::steady_clock::now()) {
    for (const MaterialSpec& m : scene.materials) material_names_.push_back(m.name);
    // For tests of the guard (docs/long-runs.md): TEAR_TEST_INJECT_NAN=STEP,ID makes particle
    // ID's velocity NaN after step STEP.
    if (const char* env = std::getenv("TEAR_TEST_INJECT_NAN"))
      std::sscanf(env, "%ld,%u", &inject_nan_step_, &inject_nan_id_);
    speed2_ = speed2_or_fault(settings_, state_);
    if (std::isinf(speed2_))
      if (const ParticleFault f = find_particle_fault(settings_, state_))
        throw std::runtime_error(
            describe(f, true) +
            (f.kind == ParticleFault::Kind::LeftDomain
                 ? ": particles must start inside the grid's domain less one cell (dx) at each "
                   "face, where they are kept; move the object inward or enlarge "
                   "grid.domain_min/max"
                 : ""));
    // The optional frame columns the scene asks for (output.fields).
    for (Particles<Dim>& g : state_.groups)
      for (const std::string& name : scene.output_fields) g.enable(name);
  }

  int dim() const override { return Dim; }
  size_t num_particles() const override { return state_.num_particles(); }
  int frame() const override { return frame_; }
  double time() const override { return state_.time; }
  long total_steps() const override { return state_.steps; }
  double estimate_dt() const override { return dt_limits().dt(); }
  DtLimits dt_limits() const override {
    return tear::dt_limits(settings_, state_, domain_, speed2_);
  }

  double step(double dt_cap) override {
    const double planned = std::min(dt_cap, estimate_dt());
    const double dt = settings_.integrator == Integrator::Implicit
                          ? implicit_step(settings_, &state_, planned, &record_, domain_)
                          : explicit_step(settings_, &state_, planned, &record_, domain_);
    step_figures_.add(dt);
    if (state_.steps == inject_nan_step_)
      for (Particles<Dim>& g : state_.groups)
        for (size_t i = 0; i < g.size(); ++i)
          if (g.id[i] == inject_nan_id_) {
            g.v[i][0] = std::numeric_limits<Real>::quiet_NaN();
            state_.moved_step = -1;  // G2P's figures no longer describe the velocities
          }
    // The next step's speed limit, and faults (infinity): G2P recorded it.
    speed2_ = speed2_or_fault(settings_, state_);
    if (std::isinf(speed2_))
      if (const ParticleFault f = find_particle_fault(settings_, state_)) throw unstable(f, dt);
    return dt;
  }

  // Steps of estimate_dt(); the step that would cross the frame time is shortened to land
  // on it exactly (ARCHITECTURE.md "One explicit step"), unless it had to be redone shorter
  // (integrate_step): then more steps follow.
  bool advance_frame(const std::atomic<bool>* stop) override {
    if (!advance_to(*this, double(frame_ + 1) * frame_dt_, stop, &state_.time)) return false;
    ++frame_;
    return true;
  }

  FrameStats collect_stats() override {
    const StateFigures f = reduce_figures(measure_state(settings_, state_), domain_);
    FrameStats s;
    s.frame = frame_;
    s.time = state_.time;
    step_figures_.take(&s);
    s.steps_redone = record_.steps_redone;
    record_.steps_redone = 0;
    s.particles = f.particles;
    s.mass = f.mass;
    s.momentum = f.momentum;
    s.angular_momentum = f.angular_momentum;
    s.kinetic_energy = f.kinetic_energy;
    s.elastic_energy = f.elastic_energy;
    s.max_damage = f.max_damage;
    s.mean_damage = f.mean_damage;
    s.damaged_fraction = f.damaged_fraction;
    DamageSolveStats& ds = record_.damage;
    s.solver_figures = settings_.damage.solver == DamageSolver::Implicit;
    s.damage_solves = ds.solves;
    s.damage_iterations = ds.iterations;
    s.damage_iterations_max = ds.iterations_max;
    s.damage_change = ds.change_max;
    s.damage_unconverged = ds.unconverged;
    ds = DamageSolveStats();
    ImplicitSolveStats& is = record_.implicit;
    s.implicit_figures = settings_.integrator == Integrator::Implicit;
    s.newton_iterations = is.newton_iterations;
    s.newton_iterations_max = is.newton_iterations_max;
    s.cg_iterations = is.cg_iterations;
    s.newton_residual = is.residual_max;
    s.newton_unconverged = is.unconverged;
    s.cg_multigrid_solves = is.multigrid_solves;
    is = ImplicitSolveStats();
    InextensibilityStats& xs = record_.inextensibility;
    s.inextensibility_figures = has_inextensibility(settings_);
    s.inextensibility_iterations = xs.cg_iterations;
    s.inextensibility_iterations_max = xs.cg_iterations_max;
    s.inextensibility_residual = xs.residual_max;
    s.inextensibility_unconverged = xs.unconverged;
    xs = InextensibilityStats();
    s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    return s;
  }

  PointRows frame_rows() const override {
    const Particles<Dim>& p = state_.groups.at(0);  // one group per scene today
    rows_ = rows_by_id(p.id);
    return tear::frame_rows(p, rows_);
  }

  std::vector<MeshPart> frame_meshes() const override {
    std::vector<MeshPart> parts;
    for (const Particles<Dim>& el : state_.groups) {
      const int gamma = element_dimension(el.kind);
      if (gamma == 0) continue;
      const Particles<Dim>& vx = state_.groups[size_t(el.vertex_group)];
      MeshPart part;
      part.name = gamma == 1 ? "curves" : "surfaces";
      part.corners = gamma + 1;
      // Codimensional groups are never reordered: row k is particle k, id k.
      std::vector<uint32_t> rows(vx.size());
      for (size_t k = 0; k < rows.size(); ++k) rows[k] = uint32_t(k);
      const PointTable all = tear::frame_table(vx, rows);
      part.vertices.count = vx.size();
      for (const char* name : {"id", "x", "y", "z", "vx", "vy", "vz", "material"})
        part.vertices.add(name, all.types[index_of(all, name)], all.column(name));
      rows.resize(el.size());
      for (size_t k = 0; k < rows.size(); ++k) rows[k] = uint32_t(k);
      const PointTable cols = tear::frame_table(el, rows);
      part.element_columns.count = el.size();
      for (const char* name : {"id", "material", "contact", "normal_stretch"})
        part.element_columns.add(name, cols.types[index_of(cols, name)], cols.column(name));
      if (gamma == 1) {
        // A segment's radius from its volume over its rest length (codim/elements.h: V = L pi
        // r^2 in 3D, L 2 r in 2D; D^-1's first entry is 1 / L), for pictures of tubes.
        std::vector<double> radius(el.size());
        for (size_t e = 0; e < el.size(); ++e) {
          const double a = double(el.vol0[e]) * double(el.rest_inverse[e](0, 0));
          radius[e] = Dim == 3 ? std::sqrt(a / M_PI) : 0.5 * a;
        }
        part.element_columns.add("radius", ColumnType::Float32, radius);
      }
      part.elements.reserve(el.size());
      for (const std::array<uint32_t, 3>& c : el.element_vertices)
        part.elements.push_back({c[0], c[1], c[2], 0});
      parts.push_back(std::move(part));
    }
    return parts;
  }

  const PointTable& frame_table() const override {
    fill_table(frame_rows(), &table_);
    return table_;
  }

  ByteWriter checkpoint() const override { return encode(true); }
  size_t checkpoint_bytes_max() const override { return encode(false).size(); }

  void decode_checkpoint(const std::string& bytes) override {
    // Version A differs only in writing every value of every field (put_fields).
    ByteReader r = open_checkpoint(bytes, kCheckpointMagic, std::string("A") + kCheckpointMagic.back(),
                                   Dim, "a checkpoint of an FEM run (this scene is MPM)");
    const char version = bytes[kCheckpointMagic.size() - 1];
    const uint32_t groups = r.get<uint32_t>();
    if (groups != state_.groups.size())
      throw std::runtime_error("checkpoint has " + std::to_string(groups) +
                               " particle groups, the scene " +
                               std::to_string(state_.groups.size()));
    std::vector<uint64_t> counts(groups);
    for (uint32_t g = 0; g < groups; ++g) {
      counts[g] = r.get<uint64_t>();
      if (counts[g] != state_.groups[g].size())
        throw std::runtime_error("checkpoint has " + std::to_string(counts[g]) +
                                 " particles, the scene " +
                                 std::to_string(state_.groups[g].size()));
    }
    // Into fresh stores with the same fields, so that a refused checkpoint leaves the state.
    std::vector<Particles<Dim>> stores(groups);
    for (uint32_t g = 0; g < groups; ++g) {
      stores[g].kind = state_.groups[g].kind;
      stores[g].vertex_group = state_.groups[g].vertex_group;
      stores[g].enable_like(state_.groups[g]);
    }
    MpmState<Dim> state;
    state.time = r.get<double>();
    state.steps = long(r.get<int64_t>());
    state.implicit_multigrid = r.get<int32_t>() != 0;
    const int frame = r.get<int32_t>();
    StepFigures step_figures;
    step_figures.read(&r);
    const int64_t redone = r.get<int64_t>();
    DamageSolveStats ds;
    ds.solves = long(r.get<int64_t>());
    ds.iterations = long(r.get<int64_t>());
    ds.iterations_max = r.get<int32_t>();
    ds.change_max = r.get<double>();
    ds.unconverged = long(r.get<int64_t>());
    ImplicitSolveStats is;
    is.solves = long(r.get<int64_t>());
    is.newton_iterations = long(r.get<int64_t>());
    is.newton_iterations_max = r.get<int32_t>();
    is.cg_iterations = long(r.get<int64_t>());
    is.residual_max = r.get<double>();
    is.unconverged = long(r.get<int64_t>());
    is.multigrid_solves = long(r.get<int64_t>());
    InextensibilityStats xs;
    xs.solves = long(r.get<int64_t>());
    xs.cg_iterations = long(r.get<int64_t>());
    xs.cg_iterations_max = r.get<int32_t>();
    xs.residual_max = r.get<double>();
    xs.unconverged = long(r.get<int64_t>());
    for (uint32_t g = 0; g < groups; ++g)
      get_fields(&r, size_t(counts[g]), &stores[g], version != 'A');
    if (!r.at_end()) throw std::runtime_error("corrupt checkpoint (trailing bytes)");
    // What the checksum cannot vouch for (a checkpoint forged with a valid one): ids that are
    // not a permutation, particles outside the domain or not finite.
    for (const Particles<Dim>& g : stores) {
      try {
        rows_by_id(g.id);
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string("corrupt checkpoint (") + e.what() + ")");
      }
    }
    for (const Particles<Dim>& g : stores) {
      if (element_dimension(g.kind) == 0) continue;
      const size_t vertices = stores[size_t(g.vertex_group)].size();
      for (size_t e = 0; e < g.size(); ++e)
        for (uint32_t v : g.element_vertices[e])
          if (v >= vertices)
            throw std::runtime_error("corrupt checkpoint (element " + std::to_string(e) +
                                     " refers to vertex " + std::to_string(v) + " of " +
                                     std::to_string(vertices) + ")");
    }
    state.groups = std::move(stores);
    if (const ParticleFault f = find_particle_fault(settings_, state))
      throw std::runtime_error("corrupt checkpoint (" + describe(f, true) + ")");
    state_.groups = std::move(state.groups);
    state_.time = state.time;
    state_.steps = state.steps;
    state_.home_slots_step = -1;  // new positions
    state_.moved_step = -1;
    state_.implicit_multigrid = state.implicit_multigrid;
    speed2_ = speed2_or_fault(settings_, state_);
    frame_ = frame;
    step_figures_ = step_figures;
    record_.damage = ds;
    record_.implicit = is;
    record_.inextensibility = xs;
    record_.steps_redone = redone;
  }

  std::vector<std::pair<std::string, double>> phase_seconds() const override {
    const PhaseTimes& t = record_.times;
    return {{"sort", t.sort},     {"stress", t.stress},
            {"damage", t.damage}, {"crack fields", t.crack_fields},
            {"codim forces", t.codim},
            {"p2g", t.p2g},       {"grid", t.grid},
            {"inextensibility", t.inextensibility}, {"g2p", t.g2p}};
  }

  size_t memory_bytes() const override {
    size_t bytes = state_.grid.memory_bytes();
    for (const Particles<Dim>& g : state_.groups) bytes += g.memory_bytes();
    return bytes;
  }

 private:
  // compact: fields that hold one value for every particle written once (put_fields).
  ByteWriter encode(bool compact) const {
    ByteWriter w;
    w.put_bytes(kCheckpointMagic);
    w.put<int32_t>(Dim);
    w.put<int32_t>(sizeof(Real));
    w.put<uint32_t>(uint32_t(state_.groups.size()));
    for (const Particles<Dim>& g : state_.groups) w.put<uint64_t>(g.size());
    w.put<double>(state_.time);
    w.put<int64_t>(state_.steps);
    w.put<int32_t>(state_.implicit_multigrid ? 1 : 0);
    w.put<int32_t>(frame_);
    step_figures_.write(&w);
    w.put<int64_t>(record_.steps_redone);
    const DamageSolveStats& ds = record_.damage;
    w.put<int64_t>(ds.solves);
    w.put<int64_t>(ds.iterations);
    w.put<int32_t>(ds.iterations_max);
    w.put<double>(ds.change_max);
    w.put<int64_t>(ds.unconverged);
    const ImplicitSolveStats& is = record_.implicit;
    w.put<int64_t>(is.solves);
    w.put<int64_t>(is.newton_iterations);
    w.put<int32_t>(is.newton_iterations_max);
    w.put<int64_t>(is.cg_iterations);
    w.put<double>(is.residual_max);
    w.put<int64_t>(is.unconverged);
    w.put<int64_t>(is.multigrid_solves);
    const InextensibilityStats& xs = record_.inextensibility;
    w.put<int64_t>(xs.solves);
    w.put<int64_t>(xs.cg_iterations);
    w.put<int32_t>(xs.cg_iterations_max);
    w.put<double>(xs.residual_max);
    w.put<int64_t>(xs.unconverged);
    for (const Particles<Dim>& g : state_.groups) put_fields(g, &w, compact);
    put_checksum(&w);
    return w;
  }

  static size_t index_of(const PointTable& t, const std::string& name) {
    return size_t(std::find(t.names.begin(), t.names.end(), name) - t.names.begin());
  }

  std::string material_name(uint16_t m) const {
    return m < material_names_.size() ? material_names_[m] : "?";
  }

  // "particle 1234 (material jelly) left the domain at x (..), v (..)", or "... is no longer
  // finite: x (..), v (..)": the one wording of a particle fault (find_particle_fault); of a
  // state not stepped yet (`start`: sampled, or read from a checkpoint) "starts outside the
  // domain at" and "is not finite:".
  std::string describe(const ParticleFault& f, bool start = false) const {
    char where[256];
    std::snprintf(where, sizeof(where), "x (%.6g, %.6g, %.6g), v (%.6g, %.6g, %.6g)", f.x[0],
                  f.x[1], f.x[2], f.v[0], f.v[1], f.v[2]);
    return "particle " + std::to_string(f.id) + " (material " + material_name(f.material) +
           (f.kind == ParticleFault::Kind::LeftDomain
                ? (start ? ") starts outside the domain at " : ") left the domain at ")
                : (start ? ") is not finite: " : ") is no longer finite: ")) +
           where;
  }

  // "the run stopped in frame 4, step 812 (dt ..): particle 1234 (material jelly) ...".
  UnstableRun unstable(const ParticleFault& f, double dt) const {
    const bool left = f.kind == ParticleFault::Kind::LeftDomain;
    char step[96];
    std::snprintf(step, sizeof(step), "frame %d, step %ld (dt %.3g s): ", frame_ + 1,
                  state_.steps, dt);
    return UnstableRun(
        (left ? "the run stopped in " : "the simulation became unstable in ") + std::string(step) +
        describe(f) +
        (left ? "; enlarge grid.domain_min/domain_max, or keep it in with grid.walls or a "
                "collider"
              : "; lower time.cfl or time.max_dt, or check the material's parameters"));
  }

  MpmSettings settings_;
  std::vector<std::string> material_names_;
  double frame_dt_;
  MpmState<Dim> state_;
  // The largest squared particle speed (infinity: a fault), from the scan after the last step
  // (or of the state as sampled or read): estimate_dt uses it, with no pass of its own.
  Real speed2_ = 0;
  StepRecord record_;
  LocalDomain domain_;
  std::chrono::steady_clock::time_point start_;
  mutable std::vector<uint32_t> rows_;  // frame_rows()'s: particle indices in id order
  mutable PointTable table_;            // frame_table()'s, reused
  int frame_ = 0;
  long inject_nan_step_ = -1;  // TEAR_TEST_INJECT_NAN
  uint32_t inject_nan_id_ = 0;
  StepFigures step_figures_;
};

}  // namespace

std::unique_ptr<Simulation> make_mpm_simulation(const Scene& scene) {
  if (scene.dim == 2) return std::make_unique<MpmSimulation<2>>(scene);
  return std::make_unique<MpmSimulation<3>>(scene);
}

}  // namespace tear
