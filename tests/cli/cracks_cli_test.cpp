// End-to-end tests of `tear cracks` (crack figures of a run's frames) and of the time-step
// limits that `tear check` prints.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "cli_fixture.h"

namespace tear {
namespace {

using nlohmann::json;

// A fibered block torn apart by two grips (45-degree fibers, alpha -1), explicit damage.
json tearing_block() {
  return json::parse(R"({
    "name": "cli_cracks", "dim": 2, "damage": { "solver": "explicit" },
    "grid": { "dx": 0.03125, "domain_min": [0, 0], "domain_max": [1, 1] },
    "time": { "frame_dt": 0.05, "frames": 4 },
    "materials": { "m": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2,
                          "fiber_scale": [10],
                          "damage": { "sigma_c": 3, "eta": 0.05, "alpha": -1 } } },
    "objects": [ { "shape": { "type": "box", "min": [0.3, 0.3], "max": [0.7, 0.7] },
                   "material": "m", "ppc": 4,
                   "fibers": { "type": "constant", "a1": [1, 1] } } ],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0.2, 0.64], "max": [0.8, 0.75] },
        "velocity": [0, 0.4] },
      { "type": "sticky", "shape": { "type": "box", "min": [0.2, 0.25], "max": [0.8, 0.36] },
        "velocity": [0, -0.4] } ]
  })");
}

TEST_F(Cli, CracksPrintsAFrameLineAndJsonWithTheSameFigures) {
  const std::string s = write_scene(tearing_block());
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
  ASSERT_EQ(tear("cracks " + path("run")), 0) << err_;
  EXPECT_NE(out_.find("crack angle (deg)"), std::string::npos) << out_;
  ASSERT_EQ(tear("cracks " + path("run") + " --frames 4 --json"), 0) << err_;
  const json j = json::parse(out_);
  EXPECT_EQ(j["frame"], 4);
  const std::vector<json> st = stats(path("run"));
  // Same threshold as stats.jsonl's damaged_fraction.
  EXPECT_DOUBLE_EQ(j["fraction"].get<double>(), st.back()["damaged_fraction"].get<double>());
  ASSERT_GT(j["cracked"].get<long>(), 10) << out_;
  const double angle = j["angle_degrees"].get<double>();
  EXPECT_GT(angle, -90) << out_;
  EXPECT_LE(angle, 90) << out_;
  EXPECT_GT(j["width_spacings"].get<double>(), 0.5) << out_;
  // width = width_spacings x dx / ppc^(1/2) = width_spacings x 0.03125 / 2.
  EXPECT_NEAR(j["width"].get<double>(), j["width_spacings"].get<double>() * 0.015625, 1e-12);
  const json n = j["normal"];
  EXPECT_NEAR(std::hypot(n[0].get<double>(), n[1].get<double>()), 1, 1e-12) << out_;
  EXPECT_EQ(n[2].get<double>(), 0) << out_;
  // Frame 0 has nothing cracked: a dash for the direction.
  ASSERT_EQ(tear("cracks " + path("run") + " --frames 0"), 0) << err_;
  EXPECT_NE(out_.find(" - "), std::string::npos) << out_;
}

TEST_F(Cli, CracksRejectsBadInput) {
  EXPECT_EQ(tear("cracks " + path("nowhere")), 1);
  EXPECT_NE(err_.find("nowhere"), std::string::npos) << err_;
  const std::string s = write_scene(tearing_block());
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q --frames 1"), 0) << err_;
  EXPECT_EQ(tear("cracks " + path("run") + " --frames 3:1"), 2);
  EXPECT_EQ(tear("cracks " + path("run") + " --threshold 1"), 1);
  EXPECT_NE(err_.find("--threshold"), std::string::npos) << err_;
}

TEST_F(Cli, CheckNamesTheLimitThatSetsTheTimeStep) {
  json doc = tearing_block();
  const std::string s = write_scene(doc);
  ASSERT_EQ(tear("check " + s), 0) << err_;
  EXPECT_NE(out_.find("set by wave speed"), std::string::npos) << out_;
  EXPECT_NE(out_.find("explicit damage"), std::string::npos) << out_;
  EXPECT_NE(out_.find("while cracks grow"), std::string::npos) << out_;
  // A tiny mobility makes the explicit damage update the limit.
  ASSERT_EQ(tear("check " + s + " --set materials.m.damage.eta=1e-6"), 0) << err_;
  EXPECT_NE(out_.find("set by explicit damage"), std::string::npos) << out_;
  // The implicit solver has none.
  ASSERT_EQ(tear("check " + s + " --set damage.solver=implicit"), 0) << err_;
  EXPECT_EQ(out_.find("explicit damage"), std::string::npos) << out_;
}

}  // namespace
}  // namespace tear
