#include "tear/driver/bench_suite.h"

#include "tear/exec/domain.h"
#include "tear/mpm/explicit_step.h"
#include "tear/mpm/time_step.h"
#include "tear/scene/sampling.h"

#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "tear/exec/threads.h"

#include <chrono>
#include <cmath>
#include <random>

namespace tear {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
// The benchmark block's settings and state, stepped by the explicit integrator.
struct BenchRun {
  explicit BenchRun(const Scene& s)
      : settings(mpm_settings(s)), state(make_mpm_state<3>(settings, sample_scene_groups<3>(s))) {}
  double estimate_dt() const { return dt_limits(settings, state, domain).dt(); }
  void step(double dt) { explicit_step(settings, &state, dt, &record, domain); }
  MpmSettings settings;
  MpmState<3> state;
  StepRecord record;
  LocalDomain domain;
};

}  // namespace

nlohmann::json bench_stress(long evaluations) {
  constexpr int kPool = 1 << 16;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n01(0, 0.3);
  std::vector<Mat<3>> F(kPool), D(kPool);
  for (int i = 0; i < kPool; ++i) {
    Mat<3> A;
    for (int k = 0; k < 9; ++k) A.data()[k] = Real(n01(rng));
    F[i] = Mat<3>::Identity() + A;
    const Vec<3> axis = Vec<3>(Real(n01(rng)), Real(n01(rng)), Real(n01(rng))).normalized();
    D[i] = Eigen::AngleAxis<Real>(Real(n01(rng)), axis).toRotationMatrix();
  }
  nlohmann::json out;
  double ns[2] = {0, 0};
  const Model models[2] = {Model::QrAniso, Model::FixedCorotated};
  for (int m = 0; m < 2; ++m) {
    const MaterialParams mat = make_material(models[m], 1e4, 0.3, 1, 2, 1);
    double checksum = 0;
    const auto t0 = Clock::now();
    for (long e = 0; e < evaluations; ++e) {
      const int i = int(e & (kPool - 1));
      checksum += first_piola<3>(mat, F[i], D[i])(0, 0);
    }
    ns[m] = since(t0) * 1e9 / double(evaluations);
    out[model_name(models[m])] = {{"ns_per_stress", ns[m]}, {"checksum", checksum}};
  }
  out["evaluations"] = evaluations;
  out["speedup_qr_over_fixed_corotated"] = ns[1] / ns[0];
  return out;
}

// The 3D benchmark block: qr_aniso with fibers, 8 lattice particles per cell on a 64^3 grid,
// about `particles` particles, spinning.
static Scene bench_block_scene(long particles) {
  Scene s;
  s.name = "bench_block";
  s.dim = 3;
  s.dx = 1.0 / 64;
  s.domain_min = Vec3d::Zero();
  s.domain_max = Vec3d::Ones();
  s.walls = ContactType::Separate;
  s.gravity = Vec3d(0, -9.8, 0);
  s.max_dt = 1e-3;
  MaterialSpec m;
  m.name = "block";
  m.params = make_material(Model::QrAniso, 1e4, 0.3, 1, 2, 1);
  s.materials.push_back(m);
  ObjectSpec o;
  o.ppc = 8;
  o.grid_sampling = true;
  o.shape.type = Shape::Type::Box;
  o.shape.dim = 3;
  const double side = std::cbrt(double(particles) / 8) * s.dx;
  o.shape.min = Vec3d::Constant(0.5 - side / 2);
  o.shape.max = Vec3d::Constant(0.5 + side / 2);
  o.angular_velocity = Vec3d(0, 0, 1);
  o.fibers.a1 = Vec3d(1, 1, 0).normalized();
  s.objects.push_back(o);

  return s;
}

nlohmann::json bench_step(long particles, int steps, int threads) {
  const ThreadLimit limit(threads);
  const Scene s = bench_block_scene(particles);
  BenchRun sim(s);
  const double dt = sim.estimate_dt();  // fixed, so every thread count does the same work
  sim.step(dt);  // warm-up: first binning, allocation
  const PhaseTimes before = sim.record.times;
  const auto t0 = Clock::now();
  for (int i = 0; i < steps; ++i) sim.step(dt);
  const double wall = since(t0);
  const PhaseTimes& after = sim.record.times;
  const Particles<3>& p = sim.state.groups[0];
  const double n = double(p.size());
  nlohmann::json phases = {{"sort", after.sort - before.sort},
                           {"stress", after.stress - before.stress},
                           {"p2g", after.p2g - before.p2g},
                           {"grid", after.grid - before.grid},
                           {"g2p", after.g2p - before.g2p}};
  const size_t bytes = p.memory_bytes() + sim.state.grid.memory_bytes();
  return {{"threads", threads},
          {"particles", long(n)},
          {"steps", steps},
          {"wall_s", wall},
          {"particle_steps_per_s", n * steps / wall},
          {"particle_steps_per_s_per_thread", n * steps / wall / threads},
          {"phase_s", phases},
          {"active_grid_nodes", sim.state.grid.num_active_nodes()},
          {"bytes_per_particle", double(bytes) / n}};
}

nlohmann::json bench_damage(long particles, int steps, int threads) {
  const ThreadLimit limit(threads);
  Scene s = bench_block_scene(particles);
  s.gravity = Vec3d::Zero();
  s.objects[0].angular_velocity = Vec3d::Zero();
  DamageParams& d = s.materials[0].damage;
  d.enabled = true;
  d.sigma_c = 50;  // the 5% stretch below gives sigma ~ 500: Phi ~ 100 everywhere
  d.eta = 1;
  d.residual = 0.001;
  d.alpha[0] = -1;
  s.damage.l0 = 0.5 * s.dx;
  const char* names[3] = {"none", "explicit", "implicit"};
  nlohmann::json out = {{"threads", threads}, {"steps", steps}};
  double per_step[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    s.damage.solver = DamageSolver(k);
    BenchRun sim(s);
    for (Mat<3>& F : sim.state.groups[0].F) F(0, 0) = Real(1.05);
    const double dt = sim.estimate_dt();
    sim.step(dt);  // warm-up; from here on the damage field is non-zero everywhere
    const PhaseTimes before = sim.record.times;
    sim.record.damage = DamageSolveStats();
    const auto t0 = Clock::now();
    for (int i = 0; i < steps; ++i) sim.step(dt);
    per_step[k] = since(t0) / steps;
    nlohmann::json r = {{"s_per_step", per_step[k]},
                        {"damage_s_per_step", (sim.record.times.damage - before.damage) / steps},
                        {"particles", sim.state.groups[0].size()}};
    if (k > 0) r["cost_vs_none"] = per_step[k] / per_step[0];
    if (k == 2) {
      const DamageSolveStats& ds = sim.record.damage;
      r["damage_iterations_per_solve"] = ds.solves ? double(ds.iterations) / ds.solves : 0.0;
      r["damage_iterations_max"] = ds.iterations_max;
    }
    out[names[k]] = r;
  }
  return out;
}

nlohmann::json bench_codim(long particles, int steps, int threads) {
  const ThreadLimit limit(threads);
  // A sheet of n x n quads (2 n^2 triangles, (n + 1)^2 vertices: about `particles` in all) and
  // hair of 10 000 segments (500 strands of 20) falling under gravity, each with 2 vertices a
  // cell along it, each beside the bench block of as many particles.
  const int n = std::max(2, int(std::lround(std::sqrt(double(particles) / 3))));
  const double dx = 0.8 / (n / 2.0);
  auto scene_of = [&](const std::string& object, double dx) {
    char text[2048];
    std::snprintf(text, sizeof text, R"({
      "dim": 3, "grid": {"dx": %.17g, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1]},
      "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3}, "gravity": [0, -9.8, 0],
      "materials": {"cloth": {"model": "surface_qr", "E": 1e4, "nu": 0.3, "rho": 200},
                    "hair": {"model": "curve_qr", "E": 1e5, "nu": 0.3, "rho": 1300}},
      "objects": [%s]})", dx, object.c_str());
    return parse_scene(nlohmann::json::parse(text), "bench_codim");
  };
  char sheet[512];
  std::snprintf(sheet, sizeof sheet, R"({"kind": "surface", "material": "cloth", "thickness": 0.001,
    "shape": {"type": "sheet", "center": [0.5, 0.6, 0.5], "size": [0.8, 0.8], "resolution": [%d, %d],
              "triangulation": "random"}})", n, n);
  const std::string hair = R"({"kind": "curves", "material": "hair", "radius": 0.0005,
    "shape": {"type": "strands", "center": [0.5, 0.5, 0.5], "radius": 0.15, "cap_angle": 80,
              "count": 500, "length": 0.25, "segments": 20}})";
  nlohmann::json out = {{"threads", threads}, {"steps", steps}};
  auto time_run = [&](const Scene& sc) {
    BenchRun sim(sc);
    const double dt = sim.estimate_dt();
    sim.step(dt);
    const PhaseTimes before = sim.record.times;
    const auto t0 = Clock::now();
    for (int i = 0; i < steps; ++i) sim.step(dt);
    const double per_step = since(t0) / steps;
    const PhaseTimes& after = sim.record.times;
    return nlohmann::json{{"particles", sim.state.num_particles()},
                          {"s_per_step", per_step},
                          {"phase_s_per_step",
                           {{"sort", (after.sort - before.sort) / steps},
                            {"codim", (after.codim - before.codim) / steps},
                            {"p2g", (after.p2g - before.p2g) / steps},
                            {"grid", (after.grid - before.grid) / steps},
                            {"g2p", (after.g2p - before.g2p) / steps}}}};
  };
  // The hair's grid: 2 vertices a cell along a strand (12.5 mm segments).
  for (const auto& [name, object, cell] : std::vector<std::tuple<std::string, std::string, double>>{
           {"sheet", sheet, dx}, {"hair", hair, 0.025}}) {
    nlohmann::json r = time_run(scene_of(object, cell));
    const long count = r["particles"].get<long>();
    r["solid_beside"] = time_run(bench_block_scene(count));
    r["cost_vs_solid"] = r["s_per_step"].get<double>() / r["solid_beside"]["s_per_step"].get<double>();
    out[name] = r;
  }
  out["sheet"]["triangles"] = 2 * n * n;
  out["hair"]["segments"] = 10000;
  return out;
}

}  // namespace tear
