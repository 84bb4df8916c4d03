// Smoke runs of the paper's demos (examples/paper/): each scene loads, samples and takes a few
// steps at its shipped resolution with every value finite, its mass kept and its damage in
// [0, 1]. What each demo should show is in its description and docs/examples.md.
#include "tear/driver/simulation.h"
#include "tear/io/point_table.h"
#include "tear/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace tear {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> paper_scenes() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(fs::path(TEAR_SOURCE_DIR) / "examples" / "paper"))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

class PaperExample : public ::testing::TestWithParam<std::string> {};

TEST_P(PaperExample, TakesFiniteStepsKeepingMassAndDamageInRange) {
  const fs::path file = fs::path(TEAR_SOURCE_DIR) / "examples" / "paper" / (GetParam() + ".json");
  const Scene scene = load_scene(file.string());
  EXPECT_EQ(scene.name, GetParam());
  EXPECT_FALSE(scene.description.empty()) << "a paper demo says what it shows";
  std::unique_ptr<Simulation> sim = make_simulation(scene);
  ASSERT_GT(sim->num_particles(), 1000u);
  const double mass = sim->collect_stats().mass;
  for (int k = 0; k < 5; ++k) {
    const double dt = sim->step(scene.max_dt);
    EXPECT_GT(dt, 0);
  }
  const FrameStats s = sim->collect_stats();
  EXPECT_NEAR(s.mass, mass, 1e-9 * mass);
  EXPECT_TRUE(std::isfinite(s.kinetic_energy) && std::isfinite(s.elastic_energy));
  EXPECT_TRUE(s.momentum.allFinite() && s.angular_momentum.allFinite());
  const PointTable& t = sim->frame_table();
  for (size_t c = 0; c < t.names.size(); ++c) {
    for (double v : t.columns[c]) ASSERT_TRUE(std::isfinite(v)) << "column " << t.names[c];
  }
  if (t.has("damage")) {
    for (double d : t.column("damage")) ASSERT_TRUE(d >= 0 && d <= 1) << d;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, PaperExample, ::testing::ValuesIn(paper_scenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

}  // namespace
}  // namespace tear
