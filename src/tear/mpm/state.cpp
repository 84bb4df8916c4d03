#include "tear/mpm/state.h"

#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
MpmState<Dim> make_mpm_state(const MpmSettings& settings, std::vector<Particles<Dim>> groups) {
  MpmState<Dim> state;
  state.groups = std::move(groups);
  if (settings.damage.solver != DamageSolver::None)
    for (Particles<Dim>& g : state.groups) g.enable("drive");
  if (has_stress_phase(settings))
    for (Particles<Dim>& g : state.groups) g.enable("stress"), g.enable("J");
  if (settings.damage.split_fields)
    for (Particles<Dim>& g : state.groups) g.enable("damage_gradient");
  for (const PlasticParams& m : settings.material_plasticity) {
    if (m.surface == YieldSurface::None) continue;
    for (Particles<Dim>& g : state.groups) g.enable("plastic_strain");
    if (m.surface == YieldSurface::DruckerPrager && m.volume_correction)
      for (Particles<Dim>& g : state.groups) g.enable("plastic_volume");
  }
  for (const InextensibleParams& m : settings.material_inextensibility)
    if (m.enabled)
      for (Particles<Dim>& g : state.groups) g.enable("fiber_tension");
  state.grid.setup(settings.domain_min, settings.domain_max, settings.dx);
  sort_particles(&state);
  return state;
}

template <int Dim>
MpmState<Dim> make_mpm_state(const MpmSettings& settings, Particles<Dim> group) {
  std::vector<Particles<Dim>> groups;
  groups.push_back(std::move(group));
  return make_mpm_state<Dim>(settings, std::move(groups));
}

template MpmState<2> make_mpm_state<2>(const MpmSettings&, Particles<2>);
template MpmState<3> make_mpm_state<3>(const MpmSettings&, Particles<3>);
template MpmState<2> make_mpm_state<2>(const MpmSettings&, std::vector<Particles<2>>);
template MpmState<3> make_mpm_state<3>(const MpmSettings&, std::vector<Particles<3>>);

}  // namespace tear
