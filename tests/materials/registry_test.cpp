// The model registry (registry.h): names, traits and dispatch agree with the model files.
#include "tear/materials/registry.h"

#include <set>
#include <string>

#include "material_test_util.h"
#include "tear/materials/helpers.h"

namespace tear {
namespace {

using namespace material_test;

TEST(Registry, EveryModelRoundTripsThroughItsName) {
  for (const ModelTraits& t : kModelTraits) {
    EXPECT_STREQ(model_name(t.model), t.name);
    Model parsed = Model(-1);
    ASSERT_TRUE(parse_model(t.name, &parsed)) << t.name;
    EXPECT_EQ(parsed, t.model) << t.name;
  }
}

TEST(Registry, NamesAreUniqueAndOthersAreRejected) {
  std::set<std::string> names;
  for (const ModelTraits& t : kModelTraits) EXPECT_TRUE(names.insert(t.name).second) << t.name;
  EXPECT_EQ(int(names.size()), Models::kCount);
  Model parsed = Model::NeoHookean;
  EXPECT_FALSE(parse_model("qr-aniso", &parsed));
  EXPECT_FALSE(parse_model("", &parsed));
  EXPECT_FALSE(parse_model("QR_ANISO", &parsed));
  EXPECT_EQ(parsed, Model::NeoHookean);  // untouched on failure
  EXPECT_STREQ(model_name(Model(Models::kCount)), "?");
}

// visit_model(v, fn) calls fn with the struct whose kModel is v, for every registered v.
TEST(Registry, DispatchReachesTheModelOfEachValue) {
  for (const ModelTraits& t : kModelTraits) {
    const char* reached = visit_model(t.model, [](auto model) { return decltype(model)::kName; });
    EXPECT_STREQ(reached, t.name);
    const Model value = visit_model(t.model, [](auto model) { return decltype(model)::kModel; });
    EXPECT_EQ(value, t.model);
  }
}

// The error lists of the scene layer: every name in order; trait filters.
TEST(Registry, NameListsFollowTheRegistryOrderAndTraits) {
  std::string all;
  for (int i = 0; i < Models::kCount; ++i) all += std::string(i ? ", " : "") + model_name(Model(i));
  EXPECT_EQ(model_names(), all);
  EXPECT_EQ(model_names(&ModelTraits::has_fiber_stiffness), "qr_aniso, surface_qr");
  EXPECT_EQ(model_names(&ModelTraits::degraded_by_damage), "qr_aniso");
}

// kHasFiberStiffness says whether make_material turns fiber scales into kx, ky.
TEST(Registry, FiberTraitMatchesTheParameterMapping) {
  for (const ModelTraits& t : kModelTraits) {
    const MaterialParams m = make_material(t.model, 1000, 0.3, 1, 4, 2);
    EXPECT_EQ(m.kx > 0 && m.ky > 0, t.has_fiber_stiffness) << t.name;
    EXPECT_EQ(m.kx == 0 && m.ky == 0, !t.has_fiber_stiffness) << t.name;
  }
}

// kDegradedByDamage says whether g changes the energy and the stress.
TEST(Registry, DamageTraitMatchesWhetherDegradationChangesTheStress) {
  std::mt19937_64 rng(3);
  const Mat<3> F = Mat<3>::Identity() + random_matrix<3>(rng, 0.2) + 0.1 * Mat<3>::Identity();
  const Mat<3> D = random_rotation<3>(rng);
  for (const ModelTraits& t : kModelTraits) {
    const MaterialParams m = make_material(t.model, 1000, 0.3, 1);
    const bool stress_changes = first_piola<3>(m, F, D, 0.3) != first_piola<3>(m, F, D, 1);
    const bool energy_changes = energy_density<3>(m, F, D, 0.3) != energy_density<3>(m, F, D, 1);
    EXPECT_EQ(stress_changes, t.degraded_by_damage) << t.name;
    EXPECT_EQ(energy_changes, t.degraded_by_damage) << t.name;
  }
}

}  // namespace
}  // namespace tear
