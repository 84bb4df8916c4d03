// Shared helpers for the scene tests: a minimal valid scene and error capture.
#pragma once

#include "tear/scene/scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace tear::test {

// Smallest valid 2D scene: one box of "jelly".
inline nlohmann::json minimal_scene_2d() {
  return nlohmann::json::parse(R"({
    "dim": 2,
    "grid": { "dx": 0.05, "domain_min": [0, 0], "domain_max": [1, 1] },
    "time": { "frame_dt": 0.01, "frames": 2 },
    "materials": { "jelly": { "model": "neo_hookean", "E": 1000, "nu": 0.3, "rho": 2 } },
    "objects": [ { "shape": { "type": "box", "min": [0.2, 0.2], "max": [0.6, 0.6] },
                   "material": "jelly" } ]
  })");
}

// A 3D scene over the unit cube (dx 0.02) with one object, the mesh `file` (relative to the
// scene file) sampled by `sampling` at `ppc` particles a cell.
inline nlohmann::json mesh_scene(const std::string& file, const std::string& sampling, int ppc) {
  nlohmann::json doc = minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.02}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["objects"][0] = {{"shape", {{"type", "mesh"}, {"file", file}}},
                       {"material", "jelly"},
                       {"sampling", sampling},
                       {"ppc", ppc}};
  return doc;
}

// The SceneError message of parsing `doc`, or "" when it parses.
inline std::string scene_error(const nlohmann::json& doc, const std::string& file = "broken.json") {
  try {
    parse_scene(doc, file);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

// A fresh file under the test temp dir holding `text`.
inline std::string write_temp(const std::string& name, const std::string& text) {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / "tear_scene_tests";
  std::filesystem::create_directories(dir);
  std::filesystem::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

// A fresh file `name` in folder `dir` holding `text`.
inline std::string write_temp_in(const std::string& dir, const std::string& name,
                                 const std::string& text) {
  std::filesystem::create_directories(dir);
  const std::filesystem::path p = std::filesystem::path(dir) / name;
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace tear::test
