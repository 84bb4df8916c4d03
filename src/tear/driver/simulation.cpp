#include "tear/driver/simulation.h"

namespace tear {

std::unique_ptr<Simulation> make_simulation(const Scene& scene) {
  if (!scene.objects.empty() && scene.objects[0].fem) return make_fem_simulation(scene);
  return make_mpm_simulation(scene);
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
