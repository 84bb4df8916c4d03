// The plastic projection phase: each plastic particle's F back onto its yield surface.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
void project_plastic(const MpmSettings& settings, MpmState<Dim>* state) {
  for (Particles<Dim>& p : state->groups) {
    if (element_dimension(p.kind) > 0) {  // codimensional elements: their friction
      parallel_for(p.size(), [&](size_t i) {
        p.contact[i] = uint8_t(codim_return_map<Dim>(settings.materials[p.material[i]], &p.F[i]));
      });
      continue;
    }
    if (!p.enabled("plastic_strain")) continue;  // no plastic material
    const bool volume = p.enabled("plastic_volume");
    parallel_for(p.size(), [&](size_t i) {
      const PlasticParams& m = settings.material_plasticity[p.material[i]];
      if (m.surface == YieldSurface::None) return;
      PlasticState s{p.plastic_strain[i], volume ? p.plastic_volume[i] : Real(0)};
      return_map<Dim>(m, &p.F[i], &s);
      p.plastic_strain[i] = s.strain;
      if (volume) p.plastic_volume[i] = s.volume;
    });
  }
}

template void project_plastic<2>(const MpmSettings&, MpmState<2>*);
template void project_plastic<3>(const MpmSettings&, MpmState<3>*);

}  // namespace tear
