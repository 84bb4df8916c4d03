// Scene -> the MPM core's plain settings.
#include "tear/scene/scene.h"

namespace tear {

MpmSettings mpm_settings(const Scene& scene) {
  MpmSettings s;
  s.dx = scene.dx;
  s.domain_min = scene.domain_min;
  s.domain_max = scene.domain_max;
  s.cfl = scene.cfl;
  s.max_dt = scene.max_dt;
  s.gravity = scene.gravity;
  s.transfer = scene.transfer;
  s.integrator = scene.integrator;
  s.newton = scene.newton;
  s.implicit_preconditioner = scene.implicit_preconditioner;
  s.inextensibility = scene.inextensibility;
  s.flip_ratio = scene.flip_ratio;
  s.flip_relaxation_time = scene.flip_relaxation_time;
  s.walls = scene.walls;
  s.colliders = scene.boundaries;
  s.damage = scene.damage;
  // Nothing cracks without a damage solver, so no node would ever be split.
  if (scene.damage.solver == DamageSolver::None) s.damage.split_fields = false;
  for (const MaterialSpec& m : scene.materials) {
    s.materials.push_back(m.params);
    DamageParams d = m.damage;
    if (scene.damage.solver == DamageSolver::None) d.enabled = false;
    s.material_damage.push_back(d);
    s.material_plasticity.push_back(m.plasticity);
    s.material_inextensibility.push_back(m.inextensibility);
  }
  return s;
}

}  // namespace tear
