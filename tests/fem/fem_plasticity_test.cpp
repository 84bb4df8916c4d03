// Plasticity on FEM elements (fem_plastic_flow): von Mises with linear hardening under a uniform
// isochoric stretch follows the analytic stress-strain curve, and the elements' new rest shape
// is the permanent set; a plastic body resumes from a checkpoint bit for bit.
#include "tear/driver/simulation.h"
#include "tear/fem/fem.h"
#include "tear/materials/registry.h"
#include "tear/scene/scene.h"
#include "fem_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace tear {
namespace {

using test::structured_box;

// Uniaxial isochoric stretch exp(l) along x (3D: F = diag(e^l, e^-l/2, e^-l/2)), applied to
// every node of a box of 6 tetrahedra in steps of dl, flowing after each. The Hencky strain's
// deviator has norm e = sqrt(3/2) l; elastic, sqrt(3/2) |dev tau| = sqrt(6) mu e. Past yield the
// radial return is exact for this monotonic, coaxial path: the plastic strain's norm is
// p = (sqrt(6) mu e - sigma_y) / (sqrt(6) mu + sqrt(2/3) H) and the von Mises stress
// sigma_y + sqrt(2/3) H p. Releasing the body to x = exp(eps_p) X (eps_p = p / sqrt(3/2)
// diag(1, -1/2, -1/2)) leaves no stress: the permanent set.
TEST(FemPlasticity, VonMisesFollowsTheHardeningCurveAndKeepsThePermanentSet) {
  const double E = 1e4, nu = 0.3, sigma_y = 50;
  const double mu = E / (2 * (1 + nu));
  for (double H : {0.0, 2000.0}) {
    SCOPED_TRACE(H);
    MpmSettings s;
    s.dx = 0.05;
    s.domain_min = Vec3d::Constant(-10);
    s.domain_max = Vec3d::Constant(10);
    s.walls = ContactType::None;
    s.materials = {make_material(Model::StvkHencky, Real(E), Real(nu), 1000, 0, 0)};
    s.material_plasticity = {von_mises(Real(E), Real(nu), Real(sigma_y), Real(H))};
    ASSERT_TRUE(fem_plastic(s));
    const FemMesh mesh = structured_box(3, Vec3d::Zero(), Vec3d(0.2, 0.1, 0.1), {2, 1, 1});
    FemState<3> st;
    append_fem_body<3>(mesh, s.materials, [](const Vec3d&, size_t) { return ElementSetup<3>{}; },
                       Vec3d::Zero(), Vec3d::Zero(), Vec3d::Zero(), &st);
    const auto place = [&](double l) {
      const Vec3d f(std::exp(l), std::exp(-l / 2), std::exp(-l / 2));
      for (size_t i = 0; i < mesh.nodes.size(); ++i)
        st.nodes.x[i] = mesh.nodes[i].cwiseProduct(f).cast<Real>();
    };
    const double dl = 5e-4;
    size_t yielded_first = 0;
    for (int k = 1; k <= 40; ++k) {
      const double l = k * dl;
      place(l);
      const size_t yielded = fem_plastic_flow(s, &st);
      const double e = std::sqrt(1.5) * l;
      const double trial = std::sqrt(6.0) * mu * e;
      double p = 0, want = trial;
      if (trial > sigma_y) {
        p = (trial - sigma_y) / (std::sqrt(6.0) * mu + std::sqrt(2.0 / 3) * H);
        want = sigma_y + std::sqrt(2.0 / 3) * H * p;
      }
      EXPECT_EQ(yielded, trial > sigma_y ? st.elements.size() : 0u) << "step " << k;
      if (yielded && !yielded_first) yielded_first = size_t(k);
      const FemElementFigures f = fem_element_figures(s, st);
      for (size_t el = 0; el < st.elements.size(); ++el) {
        ASSERT_NEAR(f.von_mises[el], want, 1e-4 * want) << "step " << k << " element " << el;
        ASSERT_NEAR(f.plastic_strain[el], std::sqrt(2.0 / 3) * p, 1e-6) << "step " << k;
        ASSERT_NEAR(f.J[el], 1, 1e-5);
      }
      if (k == 40) {
        // Released to the permanent set: no stress anywhere.
        place(p / std::sqrt(1.5));
        EXPECT_LT(fem_elastic_energy(s, st, st.nodes.x), 1e-9 * 0.002 * sigma_y * sigma_y / E);
        const FemElementFigures rest = fem_element_figures(s, st);
        for (size_t el = 0; el < st.elements.size(); ++el) EXPECT_LT(rest.von_mises[el], 1e-3);
      }
    }
    // Yield at sqrt(6) mu sqrt(3/2) l = sigma_y: l = sigma_y / (3 mu) = 0.00433, step 9.
    EXPECT_EQ(yielded_first, size_t(std::ceil(sigma_y / (3 * mu) / dl)));
    EXPECT_EQ(yielded_first, 9u);
  }
}

// A soft plastic block dropped onto the floor flattens for good; resumed from a checkpoint in
// mid-fall it ends in the same bytes, plastic state included; an elastic scene refuses the
// plastic checkpoint.
TEST(FemPlasticity, PlasticBodyResumesBitForBit) {
  const std::string text = R"({"dim": 2,
      "grid": {"dx": 0.05, "domain_min": [0, 0], "domain_max": [1, 1], "walls": "slip"},
      "time": {"frame_dt": 0.03, "frames": 6, "max_dt": 0.005},
      "gravity": [0, -9.81], "integrator": "implicit",
      "materials": {"clay": {"model": "stvk_hencky", "E": 2e4, "nu": 0.3, "rho": 1000,
                             "plasticity": {"type": "von_mises", "yield_stress": 300}}},
      "objects": [{"simulation": "fem", "mesh_size": 0.05, "material": "clay", "velocity": [0, -2],
                   "shape": {"type": "box", "min": [0.3, 0.25], "max": [0.7, 0.45]}}]})";
  const Scene s = load_scene_text(text, "fem_plastic.json");
  std::string mid;
  const auto whole = test::expect_resumes_identically(s, 6, &mid);
  // It yielded where it struck.
  const std::vector<MeshPart> parts = whole->frame_meshes();
  ASSERT_TRUE(parts.at(0).element_columns.has("plastic_strain"));
  const std::vector<double> ep = parts[0].element_columns.column("plastic_strain");
  EXPECT_GT(*std::max_element(ep.begin(), ep.end()), 1e-3);
  std::string elastic = text;
  const size_t at = elastic.rfind(',', elastic.find(R"("plasticity")"));
  elastic.erase(at, elastic.find('}', at) + 1 - at);
  ASSERT_EQ(elastic.find("yield"), std::string::npos) << elastic;
  auto other = make_simulation(load_scene_text(elastic, "fem_elastic.json"));
  EXPECT_THROW(other->decode_checkpoint(mid), std::runtime_error);
}

}  // namespace
}  // namespace tear
