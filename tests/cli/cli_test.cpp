// End-to-end tests of the `tear` executable: outputs, determinism, resume, bad input.
#include "tear/io/atomic_file.h"
#include "tear/io/ply.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>

namespace tear {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("tear_cli_test_" + std::to_string(rd()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // A small 2D scene: an anisotropic disk with some spin falling onto a sticky floor, and a
  // moving collider, so every part of the step runs.
  json scene() const {
    return json::parse(R"({
      "name": "cli_test", "dim": 2, "seed": 3,
      "grid": { "dx": 0.03125, "domain_min": [0, 0], "domain_max": [1, 1] },
      "time": { "frame_dt": 0.02, "frames": 4 },
      "gravity": [0, -9.8],
      "materials": { "jelly": { "model": "qr_aniso", "E": 500, "nu": 0.3, "rho": 1,
                                "fiber_scale": [4] } },
      "objects": [ { "shape": { "type": "sphere", "center": [0.5, 0.5], "radius": 0.15 },
                     "material": "jelly", "ppc": 4, "velocity": [0.2, -0.5],
                     "angular_velocity": 3,
                     "fibers": { "type": "constant", "a1": [1, 1] } } ],
      "boundaries": [
        { "type": "slip", "friction": 0.3,
          "shape": { "type": "half_space", "point": [0, 0.2], "normal": [0, 1] } },
        { "type": "sticky", "shape": { "type": "box", "min": [0.3, 0.62], "max": [0.7, 0.7] },
          "velocity": [0, 0.3], "start": 0, "end": 0.05 } ],
      "output": { "every": 1, "checkpoint_every": 1 }
    })");
  }

  std::string write_scene(const json& j, const std::string& name = "scene.json") const {
    write_file_atomic(path(name), j.dump(2));
    return path(name);
  }

  // Runs `tear ARGS`; returns the exit code, output in out_ (stdout and stderr).
  int tear(const std::string& args) {
    const std::string log = path("log.txt");
    const std::string cmd = std::string(TEAR_CLI) + " " + args + " > " + log + " 2>&1";
    const int status = std::system(cmd.c_str());
    out_ = read_file(log);
    return WEXITSTATUS(status);
  }

  std::vector<json> stats(const std::string& run) const {
    std::vector<json> lines;
    std::istringstream in(read_file(run + "/stats.jsonl"));
    std::string line;
    while (std::getline(in, line)) lines.push_back(json::parse(line));
    return lines;
  }

  fs::path dir_;
  std::string out_;
};

TEST_F(Cli, RunWritesTheDocumentedOutputs) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << out_;
  EXPECT_NE(out_.find("wrote 4 frames"), std::string::npos) << out_;
  for (int f = 0; f <= 4; ++f) EXPECT_TRUE(fs::exists(path("run/frames/0000" + std::to_string(f) + ".ply")));
  EXPECT_FALSE(fs::exists(path("run/frames/00005.ply")));
  EXPECT_TRUE(fs::exists(path("run/checkpoints/latest.bin")));
  // scene.json is the resolved scene: defaults filled in.
  const json resolved = json::parse(read_file(path("run/scene.json")));
  EXPECT_EQ(resolved["transfer"], "apic");
  EXPECT_EQ(resolved["time"]["cfl"], 0.4);
  // Frames: the documented columns, rows sorted by id.
  const PlyTable t = decode_ply(read_file(path("run/frames/00004.ply")));
  for (const char* c : {"id", "x", "y", "z", "vx", "vy", "vz", "damage", "material", "fx", "fy", "fz"})
    EXPECT_TRUE(t.has(c)) << c;
  ASSERT_GT(t.count, 200u);
  for (size_t i = 0; i < t.count; ++i) ASSERT_EQ(t.column("id")[i], double(i));
  EXPECT_EQ(t.column("z"), std::vector<double>(t.count, 0.0));
  // stats.jsonl: one line per frame with the documented keys; mass is exactly conserved.
  const std::vector<json> lines = stats(path("run"));
  ASSERT_EQ(lines.size(), 5u);
  for (size_t f = 0; f < lines.size(); ++f) {
    for (const char* k : {"frame", "time", "steps", "dt_min", "dt_max", "particles", "mass",
                          "momentum", "angular_momentum", "kinetic_energy", "elastic_energy",
                          "max_damage", "mean_damage", "damaged_fraction", "wall_s"})
      EXPECT_TRUE(lines[f].contains(k)) << k;
    EXPECT_EQ(lines[f]["frame"], int(f));
    EXPECT_EQ(lines[f]["mass"], lines[0]["mass"]);
    EXPECT_EQ(lines[f]["momentum"].size(), 3u);
  }
  EXPECT_NEAR(lines[4]["time"].get<double>(), 0.08, 1e-15);  // steps land on frame times
  EXPECT_GT(lines[4]["steps"].get<int>(), 0);
  EXPECT_EQ(tear("check " + s), 0) << out_;
  EXPECT_NE(out_.find("particles  " + std::to_string(t.count)), std::string::npos) << out_;
}

TEST_F(Cli, OutputIsBitIdenticalForOneAndTwoThreads) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("t1") + " -q --threads 1"), 0) << out_;
  ASSERT_EQ(tear("run " + s + " -o " + path("t2") + " -q --threads 2"), 0) << out_;
  ASSERT_EQ(tear("run " + s + " -o " + path("t2b") + " -q --threads 2"), 0) << out_;
  for (int f = 0; f <= 4; ++f) {
    const std::string name = "/frames/0000" + std::to_string(f) + ".ply";
    EXPECT_EQ(read_file(path("t1") + name), read_file(path("t2") + name)) << name;
    EXPECT_EQ(read_file(path("t2") + name), read_file(path("t2b") + name)) << name;
  }
  EXPECT_EQ(read_file(path("t1/checkpoints/latest.bin")), read_file(path("t2/checkpoints/latest.bin")));
}

TEST_F(Cli, ResumedRunMatchesAnUninterruptedOne) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("full") + " -q"), 0) << out_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --frames 2"), 0) << out_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " --resume --frames 4"), 0) << out_;
  EXPECT_NE(out_.find("resuming"), std::string::npos) << out_;
  EXPECT_EQ(read_file(path("full/frames/00004.ply")), read_file(path("part/frames/00004.ply")));
  const std::vector<json> a = stats(path("full")), b = stats(path("part"));
  ASSERT_EQ(b.size(), 5u);
  for (size_t f = 0; f < a.size(); ++f) {
    EXPECT_EQ(a[f]["momentum"], b[f]["momentum"]) << f;
    EXPECT_EQ(a[f]["steps"], b[f]["steps"]) << f;
  }
  // Resuming a finished run is not an error; resuming with a changed scene is.
  EXPECT_EQ(tear("run " + s + " -o " + path("part") + " --resume --frames 4"), 0) << out_;
  EXPECT_NE(out_.find("already complete"), std::string::npos);
  EXPECT_EQ(tear("run " + s + " -o " + path("part") + " --resume --set materials.jelly.E=600"), 1);
  EXPECT_NE(out_.find("scene differs"), std::string::npos) << out_;
  EXPECT_EQ(tear("run " + s + " -o " + path("nothing_here") + " --resume"), 1);
  EXPECT_NE(out_.find("no earlier run"), std::string::npos) << out_;
}

TEST_F(Cli, SetAndFramesOverrideTheScene) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("o") + " -q --frames 2 --set materials.jelly.E=750"
                 " --set 'gravity=[0,-1]'"),
            0)
      << out_;
  const json resolved = json::parse(read_file(path("o/scene.json")));
  EXPECT_EQ(resolved["materials"]["jelly"]["E"], 750);
  EXPECT_EQ(resolved["gravity"], json::parse("[0,-1]"));
  EXPECT_EQ(resolved["time"]["frames"], 2);
  EXPECT_TRUE(fs::exists(path("o/frames/00002.ply")));
  EXPECT_FALSE(fs::exists(path("o/frames/00003.ply")));
}

TEST_F(Cli, BadInputFailsWithAReasonAndWritesNothing) {
  struct Case {
    std::string name, edit, expected;
  };
  json typo = scene();
  typo["materials"]["jelly"]["nuu"] = 0.3;
  json bad_nu = scene();
  bad_nu["materials"]["jelly"]["nu"] = 0.5;
  json bad_type = scene();
  bad_type["grid"]["dx"] = "small";
  const std::vector<std::pair<json, std::string>> cases = {
      {typo, "materials.jelly.nuu"}, {bad_nu, "materials.jelly.nu"}, {bad_type, "grid.dx"}};
  for (const auto& [doc, expected] : cases) {
    const std::string s = write_scene(doc, "bad.json");
    EXPECT_EQ(tear("run " + s + " -o " + path("never")), 1) << expected;
    EXPECT_NE(out_.find("bad.json"), std::string::npos) << out_;
    EXPECT_NE(out_.find(expected), std::string::npos) << out_;
    EXPECT_EQ(out_.find('\n'), out_.size() - 1) << "one line: " << out_;
    EXPECT_FALSE(fs::exists(path("never"))) << expected;
    EXPECT_EQ(tear("check " + s), 1);
  }
  EXPECT_EQ(tear("run " + path("missing.json") + " -o " + path("never")), 1);
  EXPECT_NE(out_.find("missing.json"), std::string::npos) << out_;
  EXPECT_FALSE(fs::exists(path("never")));
  const std::string s = write_scene(scene());
  EXPECT_EQ(tear("run " + s + " -o " + path("never") + " --set nosuch.key=1"), 1);
  EXPECT_FALSE(fs::exists(path("never")));
}

TEST_F(Cli, UsageInfoAndBench) {
  EXPECT_EQ(tear(""), 2);
  EXPECT_EQ(tear("run"), 2);
  EXPECT_EQ(tear("run --threads -3 x.json -o y"), 2);
  EXPECT_EQ(tear("--help"), 0);
  EXPECT_NE(out_.find("run"), std::string::npos);
  EXPECT_EQ(tear("run --help"), 0);
  EXPECT_NE(out_.find("--resume"), std::string::npos);
  EXPECT_EQ(tear("info"), 0);
  EXPECT_NE(out_.find("precision"), std::string::npos);
  EXPECT_EQ(tear("bench --stress-evals 20000 --particles 2000 --steps 2 --threads-list 1"), 0) << out_;
  const json b = json::parse(out_.substr(out_.find("{\n")));  // after the stderr notes
  EXPECT_GT(b["stress"]["speedup_qr_over_fixed_corotated"].get<double>(), 1.0);
  ASSERT_EQ(b["step"].size(), 1u);
  EXPECT_GT(b["step"][0]["particle_steps_per_s"].get<double>(), 0);
  EXPECT_GT(b["step"][0]["particles"].get<long>(), 1000);
}

}  // namespace
}  // namespace tear
