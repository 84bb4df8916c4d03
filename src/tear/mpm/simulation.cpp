#include "tear/mpm/simulation.h"

#include "tear/io/binary.h"
#include "tear/math/parallel.h"
#include "tear/mpm/solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace tear {

nlohmann::json PhaseTimes::to_json() const {
  return {{"sort", sort}, {"damage", damage}, {"p2g", p2g}, {"grid", grid}, {"g2p", g2p},
          {"other", other}};
}

nlohmann::json FrameStats::to_json() const {
  auto vec = [](const Vec3d& v) { return nlohmann::json::array({v[0], v[1], v[2]}); };
  nlohmann::json j = {{"frame", frame},
          {"time", time},
          {"steps", steps},
          {"dt_min", dt_min},
          {"dt_max", dt_max},
          {"particles", particles},
          {"mass", mass},
          {"momentum", vec(momentum)},
          {"angular_momentum", vec(angular_momentum)},
          {"kinetic_energy", kinetic_energy},
          {"elastic_energy", elastic_energy},
          {"max_damage", max_damage},
          {"mean_damage", mean_damage},
          {"damaged_fraction", damaged_fraction},
          {"wall_s", wall_s}};
  if (solver_figures) {
    j["damage_solves"] = damage_solves;
    j["damage_iterations"] = damage_iterations;
    j["damage_iterations_max"] = damage_iterations_max;
    j["damage_unconverged"] = damage_unconverged;
    j["damage_change"] = damage_change;
  }
  return j;
}

namespace {

const std::string kCheckpointMagic = "TEARCKP4";

template <int Dim>
class MpmSimulation final : public Simulation {
 public:
  explicit MpmSimulation(const Scene& scene)
      : solver_(scene), start_(std::chrono::steady_clock::now()) {}

  int dim() const override { return Dim; }
  size_t num_particles() const override { return solver_.particles().size(); }
  int frame() const override { return frame_; }
  double time() const override { return solver_.time(); }
  long total_steps() const override { return solver_.steps(); }
  double estimate_dt() const override { return solver_.estimate_dt(); }
  DtLimits dt_limits() const override { return solver_.dt_limits(); }
  const PhaseTimes& phase_times() const override { return solver_.phase_times(); }

  double step(double dt_cap) override {
    const double dt = std::min(dt_cap, solver_.estimate_dt());
    solver_.step(dt);
    dt_min_ = std::min(dt_min_, dt);
    dt_max_ = std::max(dt_max_, dt);
    ++steps_since_stats_;
    return dt;
  }

  // Steps of estimate_dt(); the step that would cross the frame time is shortened to land
  // on it exactly (ARCHITECTURE.md "One explicit step").
  void advance_frame() override {
    const double target = double(frame_ + 1) * solver_.scene().frame_dt;
    while (solver_.time() < target) {
      const double remaining = target - solver_.time();
      const double dt = solver_.estimate_dt();
      if (dt >= remaining * (1 - 1e-9)) {
        step(remaining);
        solver_.set_time(target);
      } else {
        step(dt);
      }
    }
    ++frame_;
  }

  FrameStats collect_stats() override {
    const Particles<Dim>& p = solver_.particles();
    FrameStats s;
    s.frame = frame_;
    s.time = solver_.time();
    s.steps = steps_since_stats_;
    s.dt_min = steps_since_stats_ ? dt_min_ : 0;
    s.dt_max = steps_since_stats_ ? dt_max_ : 0;
    s.particles = p.size();
    s.mass = solver_.total_mass();
    s.momentum = solver_.momentum();
    s.angular_momentum = solver_.angular_momentum();
    s.kinetic_energy = solver_.kinetic_energy();
    s.elastic_energy = solver_.elastic_energy();
    const size_t n = p.size();
    if (n) {
      s.max_damage = parallel_max<double>(n, [&](size_t i) { return p.damage[i]; }, 0.0);
      s.mean_damage =
          deterministic_sum<double>(n, [&](size_t i) { return double(p.damage[i]); }) / n;
      s.damaged_fraction =
          deterministic_sum<double>(n, [&](size_t i) { return p.damage[i] > 0.5 ? 1.0 : 0.0; }) /
          n;
    }
    DamageSolveStats& ds = solver_.damage_stats();
    s.solver_figures = solver_.scene().damage.solver == DamageSolver::Implicit;
    s.damage_solves = ds.solves;
    s.damage_iterations = ds.iterations;
    s.damage_iterations_max = ds.iterations_max;
    s.damage_change = ds.change_max;
    s.damage_unconverged = ds.unconverged;
    ds = DamageSolveStats();
    s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    steps_since_stats_ = 0;
    dt_min_ = std::numeric_limits<double>::infinity();
    dt_max_ = 0;
    return s;
  }

  PointTable frame_table() const override {
    const Particles<Dim>& p = solver_.particles();
    const size_t n = p.size();
    // Rows in id order, so frame files compare row by row across frames and runs.
    std::vector<uint32_t> row(n);
    for (size_t i = 0; i < n; ++i) row[p.id[i]] = uint32_t(i);
    PointTable t;
    t.count = n;
    auto column = [&](auto&& f) {
      std::vector<double> c(n);
      for (size_t k = 0; k < n; ++k) c[k] = double(f(row[k]));
      return c;
    };
    t.add("id", ColumnType::Int32, column([&](size_t i) { return p.id[i]; }));
    const char* xs[3] = {"x", "y", "z"};
    const char* vs[3] = {"vx", "vy", "vz"};
    const char* fs[3] = {"fx", "fy", "fz"};
    for (int d = 0; d < 3; ++d) {
      t.add(xs[d], ColumnType::Float32, column([&](size_t i) { return d < Dim ? p.x[i][d] : 0; }));
    }
    for (int d = 0; d < 3; ++d) {
      t.add(vs[d], ColumnType::Float32, column([&](size_t i) { return d < Dim ? p.v[i][d] : 0; }));
    }
    t.add("damage", ColumnType::Float32, column([&](size_t i) { return p.damage[i]; }));
    t.add("material", ColumnType::UInt8, column([&](size_t i) { return p.material[i]; }));
    // World-space fiber direction: the deformed primary fiber F a1, normalised.
    std::vector<Vec<Dim>> fiber(n);
    for (size_t i = 0; i < n; ++i) {
      const Vec<Dim> f = p.F[i] * p.fiber[i].col(0);
      const Real len = f.norm();
      fiber[i] = len > 0 ? Vec<Dim>(f / len) : Vec<Dim>(p.fiber[i].col(0));
    }
    for (int d = 0; d < 3; ++d) {
      t.add(fs[d], ColumnType::Float32, column([&](size_t i) { return d < Dim ? fiber[i][d] : 0; }));
    }
    return t;
  }

  std::string encode_checkpoint() const override {
    const Particles<Dim>& p = solver_.particles();
    ByteWriter w;
    w.bytes() = kCheckpointMagic;
    w.put<int32_t>(Dim);
    w.put<int32_t>(sizeof(Real));
    w.put<uint64_t>(p.size());
    w.put<double>(solver_.time());
    w.put<int64_t>(solver_.steps());
    w.put<int32_t>(frame_);
    w.put<int64_t>(steps_since_stats_);
    w.put<double>(dt_min_);
    w.put<double>(dt_max_);
    const DamageSolveStats& ds = solver_.damage_stats();
    w.put<int64_t>(ds.solves);
    w.put<int64_t>(ds.iterations);
    w.put<int32_t>(ds.iterations_max);
    w.put<double>(ds.change_max);
    w.put<int64_t>(ds.unconverged);
    w.put_vector(p.x);
    w.put_vector(p.v);
    w.put_vector(p.C);
    w.put_vector(p.F);
    w.put_vector(p.fiber);
    w.put_vector(p.mass);
    w.put_vector(p.vol0);
    w.put_vector(p.damage);
    w.put_vector(p.drive);
    w.put_vector(p.id);
    w.put_vector(p.material);
    w.put_vector(solver_.slots_at_reorder());
    return std::move(w.bytes());
  }

  void decode_checkpoint(const std::string& bytes) override {
    if (bytes.compare(0, kCheckpointMagic.size(), kCheckpointMagic) != 0)
      throw std::runtime_error("not a tear checkpoint (or one from another version)");
    ByteReader r(bytes, kCheckpointMagic.size());
    if (r.get<int32_t>() != Dim) throw std::runtime_error("checkpoint of a different dimension");
    if (r.get<int32_t>() != int32_t(sizeof(Real)))
      throw std::runtime_error("checkpoint written with a different precision (TEAR_FLOAT)");
    const uint64_t n = r.get<uint64_t>();
    if (n != solver_.particles().size())
      throw std::runtime_error("checkpoint has " + std::to_string(n) + " particles, the scene " +
                               std::to_string(solver_.particles().size()));
    const double time = r.get<double>();
    const long steps = long(r.get<int64_t>());
    const int frame = r.get<int32_t>();
    const long since = long(r.get<int64_t>());
    const double dt_min = r.get<double>(), dt_max = r.get<double>();
    DamageSolveStats ds;
    ds.solves = long(r.get<int64_t>());
    ds.iterations = long(r.get<int64_t>());
    ds.iterations_max = r.get<int32_t>();
    ds.change_max = r.get<double>();
    ds.unconverged = long(r.get<int64_t>());
    Particles<Dim> p;
    std::vector<int> slots;
    r.get_vector(&p.x);
    r.get_vector(&p.v);
    r.get_vector(&p.C);
    r.get_vector(&p.F);
    r.get_vector(&p.fiber);
    r.get_vector(&p.mass);
    r.get_vector(&p.vol0);
    r.get_vector(&p.damage);
    r.get_vector(&p.drive);
    r.get_vector(&p.id);
    r.get_vector(&p.material);
    r.get_vector(&slots);
    for (size_t size : {p.v.size(), p.C.size(), p.F.size(), p.fiber.size(), p.mass.size(),
                        p.vol0.size(), p.damage.size(), p.drive.size(), p.id.size(),
                        p.material.size()}) {
      if (size != p.x.size()) throw std::runtime_error("corrupt checkpoint (array sizes differ)");
    }
    if (p.x.size() != n || (!slots.empty() && slots.size() != n))
      throw std::runtime_error("corrupt checkpoint (particle count)");
    if (!r.at_end()) throw std::runtime_error("corrupt checkpoint (trailing bytes)");
    solver_.restore(std::move(p), std::move(slots), time, steps);
    frame_ = frame;
    steps_since_stats_ = since;
    dt_min_ = dt_min;
    dt_max_ = dt_max;
    solver_.damage_stats() = ds;
  }

  size_t memory_bytes() const override {
    // Damage keeps each particle's undegraded stress for P2G (and, implicit, a coefficient).
    const DamageSolver ds = solver_.scene().damage.solver;
    const size_t damage_bytes = ds == DamageSolver::None ? 0
                                : ds == DamageSolver::Explicit
                                    ? sizeof(Mat<Dim>)
                                    : sizeof(Mat<Dim>) + sizeof(Real);
    return solver_.particles().size() * (Particles<Dim>::bytes_per_particle() + damage_bytes) +
           solver_.grid().memory_bytes();
  }

 private:
  MpmSolver<Dim> solver_;
  std::chrono::steady_clock::time_point start_;
  int frame_ = 0;
  long steps_since_stats_ = 0;
  double dt_min_ = std::numeric_limits<double>::infinity(), dt_max_ = 0;
};

}  // namespace

std::unique_ptr<Simulation> make_simulation(const Scene& scene) {
  if (scene.dim == 2) return std::make_unique<MpmSimulation<2>>(scene);
  return std::make_unique<MpmSimulation<3>>(scene);
}

}  // namespace tear
