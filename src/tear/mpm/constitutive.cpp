// The constitutive phase: the undegraded stress and J of every particle, once a step.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
void update_stress(const MpmSettings& settings, MpmState<Dim>* state) {
  for (Particles<Dim>& p : state->groups) {
    if (p.codimensional()) continue;  // their elements' stresses: codim_vertex_forces
    parallel_for(p.size(), [&](size_t i) {
      const MaterialParams& m = settings.materials[p.material[i]];
      p.stress[i] = first_piola<Dim>(m, p.F[i], p.fiber_of(i));
      p.J[i] = p.F[i].determinant();
    });
  }
}

template void update_stress<2>(const MpmSettings&, MpmState<2>*);
template void update_stress<3>(const MpmSettings&, MpmState<3>*);

}  // namespace tear
