#include "tear/mpm/explicit_step.h"

#include "tear/codim/elements.h"
#include "tear/damage/phase_field.h"
#include "tear/exec/phase_timer.h"
#include "tear/mpm/phases.h"
#include "tear/mpm/time_step.h"
#include "tear/particles/records.h"

#include <algorithm>
#include <array>
#include <vector>

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

// What a step writes to the state before G2P (the damage update's particle fields, the implicit
// integrator's choice of preconditioner), kept so that the step can be redone. No particle
// field is kept without damage.
template <int Dim>
class StepStart {
 public:
  StepStart(const MpmSettings& settings, const MpmState<Dim>& state)
      : implicit_multigrid_(state.implicit_multigrid) {
    if (settings.damage.solver == DamageSolver::None) return;
    for (const Particles<Dim>& p : state.groups)
      kept_.push_back({p.damage, p.drive, p.damage_laplacian});
  }
  void put_back(MpmState<Dim>* state) const {
    state->implicit_multigrid = implicit_multigrid_;
    for (size_t g = 0; g < kept_.size(); ++g) {
      Particles<Dim>& p = state->groups[g];
      p.damage = kept_[g][0];
      p.drive = kept_[g][1];
      p.damage_laplacian = kept_[g][2];
    }
  }

 private:
  bool implicit_multigrid_;
  std::vector<std::array<std::vector<Real>, 3>> kept_;
};

// The phases before the integrator's own: the undegraded stress and the damage update.
template <int Dim>
void stress_and_damage(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                       StepRecord* record, Domain& domain) {
  PhaseTimes& t = record->times;
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

}  // namespace

template <int Dim>
double integrate_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                      StepRecord* record, Domain& domain,
                      const std::function<void(double dt)>& to_grid) {
  PhaseTimes& t = record->times;
  {
    PhaseTimer timer(&t.sort);
    sort_particles(state);
  }
  // The codimensional elements' stresses and their vertices' forces: from F alone, so once for
  // every attempt below.
  if (state->has_codim()) {
    PhaseTimer timer(&t.codim);
    codim_vertex_forces(settings.materials, &state->groups);
  }
  const StepStart<Dim> start(settings, *state);
  const Real m_min = Real(domain.min(double(smallest_particle_mass(*state))));
  for (int attempt = 0;; ++attempt) {
    stress_and_damage(settings, state, dt, record, domain);
    to_grid(dt);
    const double speed = domain.max(double(grid_speed_max(*state, m_min)));
    // Not for a NaN: a shorter step would not mend it (find_particle_fault reports it).
    const bool too_far = speed * dt > kRedoCflFactor * settings.cfl * settings.dx;
    if (!too_far || attempt == kMaxRedos) break;
    start.put_back(state);
    state->grid.zero_momentum_fields();
    ++record->steps_redone;
    dt = std::min(dt / 2, settings.cfl * settings.dx / speed);
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
  for (Particles<Dim>& p : state->groups) {
    RegistryRecords records(&p, "x");
    domain.migrate(&records);
  }
  state->time += dt;
  ++state->steps;
  return dt;
}

template <int Dim>
double explicit_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                     StepRecord* record, Domain& domain) {
  PhaseTimes& t = record->times;
  return integrate_step(settings, state, dt, record, domain, [&](double h) {
    if (settings.damage.split_fields) {
      PhaseTimer timer(&t.crack_fields);
      partition_crack_fields(settings, state, domain);
    }
    {
      PhaseTimer timer(&t.p2g);
      p2g(settings, state, Real(h));
    }
    domain.sum_halos(momentum_fields(&state->grid));
    PhaseTimer timer(&t.grid);
    grid_update(settings, state, Real(h));
  });
}

template <int Dim>
void damage_only_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                      StepRecord* record, Domain& domain) {
  sort_particles(state);
  stress_and_damage(settings, state, dt, record, domain);
}

using ToGrid = std::function<void(double)>;
template double integrate_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&,
                                  const ToGrid&);
template double integrate_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&,
                                  const ToGrid&);
template double explicit_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&);
template double explicit_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&);
template void damage_only_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&);
template void damage_only_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&);

}  // namespace tear
