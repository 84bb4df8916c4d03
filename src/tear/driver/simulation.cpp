#include "tear/driver/simulation.h"

namespace tear {

std::unique_ptr<Simulation> make_simulation(const Scene& scene) {
  if (!scene.objects.empty() && scene.objects[0].fem) return make_fem_simulation(scene);
  return make_mpm_simulation(scene);
}

void StepFigures::take(FrameStats* s) {
  s->steps = steps;
  s->dt_min = steps ? dt_min : 0;
  s->dt_max = steps ? dt_max : 0;
  *this = StepFigures();
}

void StepFigures::write(ByteWriter* w) const {
  w->put<int64_t>(steps);
  w->put<double>(dt_min);
  w->put<double>(dt_max);
}

void StepFigures::read(ByteReader* r) {
  steps = long(r->get<int64_t>());
  dt_min = r->get<double>();
  dt_max = r->get<double>();
}

bool advance_to(Simulation& sim, double target, const std::atomic<bool>* stop, double* time) {
  while (*time < target) {
    if (stop && stop->load()) return false;
    const double remaining = target - *time;
    const double dt = sim.estimate_dt();
    if (dt >= remaining * (1 - 1e-9)) {
      if (sim.step(remaining) == remaining) *time = target;  // not cut shorter
    } else {
      sim.step(dt);
    }
  }
  return true;
}

ByteReader open_checkpoint(const std::string& bytes, const std::string& magic,
                           const std::string& versions, int dim, const std::string& not_ours) {
  const size_t prefix = magic.size() - 1;  // then the version
  if (bytes.size() < magic.size() || bytes.compare(0, prefix, magic, 0, prefix) != 0)
    throw std::runtime_error(bytes.compare(0, 4, "TEAR") == 0 ? not_ours
                                                               : "not a tear checkpoint");
  const char version = bytes[prefix];
  if (versions.find(version) == std::string::npos) {
    std::string readable;
    for (size_t k = 0; k < versions.size(); ++k)
      readable += (k == 0 ? "" : k + 1 == versions.size() ? " and " : ", ") +
                  std::string(1, versions[k]);
    throw std::runtime_error(std::string("checkpoint format version ") + version +
                             ", this tear reads version" + (versions.size() > 1 ? "s " : " ") +
                             readable + " (written by another version of tear)");
  }
  if (!checksum_matches(bytes))
    throw std::runtime_error("damaged: its checksum does not match (truncated or altered)");
  ByteReader r(bytes, magic.size(), bytes.size() - sizeof(uint64_t));
  if (r.get<int32_t>() != dim) throw std::runtime_error("checkpoint of a different dimension");
  if (r.get<int32_t>() != int32_t(sizeof(Real)))
    throw std::runtime_error("checkpoint written with a different precision (TEAR_FLOAT)");
  return r;
}

nlohmann::json FrameStats::to_json() const {
  auto vec = [](const Vec3d& v) { return nlohmann::json::array({v[0], v[1], v[2]}); };
  nlohmann::json j = {{"frame", frame},
                      {"time", time},
                      {"steps", steps},
                      {"dt_min", dt_min},
                      {"dt_max", dt_max},
                      {"steps_redone", steps_redone},
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
  if (implicit_figures) {
    j["newton_iterations"] = newton_iterations;
    j["newton_iterations_max"] = newton_iterations_max;
    j["cg_iterations"] = cg_iterations;
    j["newton_residual"] = newton_residual;
    j["newton_unconverged"] = newton_unconverged;
    j["cg_multigrid_solves"] = cg_multigrid_solves;
  }
  if (inextensibility_figures) {
    j["inextensibility_iterations"] = inextensibility_iterations;
    j["inextensibility_iterations_max"] = inextensibility_iterations_max;
    j["inextensibility_residual"] = inextensibility_residual;
    j["inextensibility_unconverged"] = inextensibility_unconverged;
  }
  return j;
}

}  // namespace tear
