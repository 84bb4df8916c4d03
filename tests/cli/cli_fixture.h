// The fixture of the end-to-end tests of the `tear` executable: a temporary
// folder, a small 2D scene, and a runner that captures the exit code, stdout
// and stderr.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tear/io/atomic_file.h"

namespace tear {

class Cli : public ::testing::Test {
 protected:
  using json = nlohmann::json;

  void SetUp() override {
    std::random_device rd;
    dir_ = std::filesystem::temp_directory_path() / ("tear_cli_test_" + std::to_string(rd()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string &name) const { return (dir_ / name).string(); }

  // A small 2D scene: an anisotropic disk with some spin falling onto a sticky
  // floor, and a moving collider, so every part of the step runs.
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

  std::string write_scene(const json &j, const std::string &name = "scene.json") const {
    write_file_atomic(path(name), j.dump(2));
    return path(name);
  }

  // Runs `tear ARGS`; returns the exit code, with stdout in out_ and stderr in
  // err_.
  int tear(const std::string &args) {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = std::string(TEAR_CLI) + " " + args + " > " + out + " 2> " + err;
    const int status = std::system(cmd.c_str());
    out_ = read_file(out);
    err_ = read_file(err);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  int count_frames(const std::string &run) const {
    int n = 0;
    for (const auto &e : std::filesystem::directory_iterator(run + "/frames"))
      n += e.path().extension() == ".ply";
    return n;
  }

  std::vector<json> stats(const std::string &run) const {
    std::vector<json> lines;
    std::istringstream in(read_file(run + "/stats.jsonl"));
    std::string line;
    while (std::getline(in, line)) lines.push_back(json::parse(line));
    return lines;
  }

  std::filesystem::path dir_;
  std::string out_, err_;
};

}  // namespace tear
