#include "tear/mpm/explicit_step.h"

#include "tear/damage/phase_field.h"
#include "tear/exec/phase_timer.h"
#include "tear/mpm/phases.h"
#include "tear/particles/records.h"

namespace tear {

namespace {

// The grid fields a scatter fills (summed over ranks) and a gather reads (copied to ghosts).
template <int Dim>
std::vector<NodeFieldView> momentum_fields(SparseGrid<Dim>* g) {
  const size_t n = g->num_active_nodes();
  std::vector<NodeFieldView> fields = {node_field(g->mass.data(), n, 1),
                                       node_field(g->velocity.data()->data(), n, Dim),
                                       node_field(g->velocity_old.data()->data(), n, Dim)};
  if (g->split()) {  // crack fields
    fields.push_back(node_field(g->mass2.data(), n, 1));
    fields.push_back(node_field(g->velocity2.data()->data(), n, Dim));
    fields.push_back(node_field(g->velocity_old2.data()->data(), n, Dim));
  }
  return fields;
}

}  // namespace

template <int Dim>
void begin_step(const MpmSettings& settings, MpmState<Dim>* state, double dt, StepRecord* record,
                Domain& domain) {
  PhaseTimes& t = record->times;
  {
    PhaseTimer timer(&t.sort);
    sort_particles(state);
  }
  if (has_stress_phase(settings)) {
    PhaseTimer timer(&t.stress);
    update_stress(settings, state);
  }
  if (settings.damage.solver != DamageSolver::None) {
    PhaseTimer timer(&t.damage);
    update_damage(&state->groups, &state->grid, settings.damage, settings.material_damage, dt,
                  &record->damage, domain);
  }
}

template <int Dim>
void end_step(MpmState<Dim>* state, double dt, Domain& domain) {
  for (Particles<Dim>& p : state->groups) {
    RegistryRecords records(&p, "x");
    domain.migrate(&records);
  }
  state->time += dt;
  ++state->steps;
}

template <int Dim>
void explicit_step(const MpmSettings& settings, MpmState<Dim>* state, double dt, StepRecord* record,
                   Domain& domain) {
  PhaseTimes& t = record->times;
  begin_step(settings, state, dt, record, domain);
  if (settings.damage.split_fields) {
    PhaseTimer timer(&t.crack_fields);
    partition_crack_fields(settings, state, domain);
  }
  {
    PhaseTimer timer(&t.p2g);
    p2g(settings, state, Real(dt));
  }
  domain.sum_halos(momentum_fields(&state->grid));
  {
    PhaseTimer timer(&t.grid);
    grid_update(settings, state, Real(dt));
  }
  if (has_inextensibility(settings)) {
    PhaseTimer timer(&t.inextensibility);
    enforce_inextensibility(settings, state, Real(dt), &record->inextensibility);
  }
  domain.copy_halos(momentum_fields(&state->grid));
  {
    PhaseTimer timer(&t.g2p);
    g2p(settings, state, Real(dt));
    project_plastic(settings, state);
  }
  end_step(state, dt, domain);
}

template <int Dim>
void damage_only_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                      StepRecord* record, Domain& domain) {
  sort_particles(state);
  update_stress(settings, state);
  update_damage(&state->groups, &state->grid, settings.damage, settings.material_damage, dt,
                &record->damage, domain);
}

template void begin_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&);
template void begin_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&);
template void end_step<2>(MpmState<2>*, double, Domain&);
template void end_step<3>(MpmState<3>*, double, Domain&);
template void explicit_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&);
template void explicit_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&);
template void damage_only_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&);
template void damage_only_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&);

}  // namespace tear
