// End-to-end tests of `tear convert` and of runs that write BGEO and VTU frames: the converted
// frames hold the PLY values, frames.pvd lists the VTU frames at their times, bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

// Every column of the PLY frame is in `other` with the same values.
void expect_same_values(const PointTable& ply, const PointTable& other, const std::string& what) {
  ASSERT_EQ(ply.count, other.count) << what;
  for (const std::string& name : ply.names) {
    ASSERT_TRUE(other.has(name)) << what << ": " << name;
    EXPECT_EQ(ply.column(name), other.column(name)) << what << ": " << name;
  }
}

// The (timestep, file) pairs of a frames.pvd, in order.
std::vector<std::pair<double, std::string>> pvd_entries(const std::string& path) {
  const std::string text = read_file(path);
  const std::regex entry("<DataSet timestep=\"([^\"]*)\"[^>]* file=\"([^\"]*)\"/>");
  std::vector<std::pair<double, std::string>> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), entry);
       it != std::sregex_iterator(); ++it)
    out.emplace_back(std::stod((*it)[1]), (*it)[2]);
  return out;
}

class ConvertCli : public Cli {
 protected:
  // A finished small run (frames 0..4, PLY only) in path("run").
  std::string run_folder() {
    const std::string s = write_scene(scene());
    EXPECT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
    return path("run");
  }
};

TEST_F(ConvertCli, ToBgeoAndVtuKeepThePlyValues) {
  const std::string run = run_folder();
  ASSERT_EQ(tear("convert " + run + " --to bgeo"), 0) << err_;
  EXPECT_NE(out_.find("converted 5 frames of " + run + " to bgeo (0 already bgeo)"),
            std::string::npos)
      << out_;
  ASSERT_EQ(tear("convert " + run + " --to vtu"), 0) << err_;
  EXPECT_NE(out_.find("converted 5 frames of " + run + " to vtu"), std::string::npos) << out_;
  EXPECT_NE(out_.find("frames.pvd (5 frames)"), std::string::npos) << out_;
  for (int f = 0; f <= 4; ++f) {
    const PointTable ply = read_frame(frame_path(run, f, "ply"));
    expect_same_values(ply, read_frame(frame_path(run, f, "bgeo")), "bgeo " + std::to_string(f));
    expect_same_values(ply, read_frame(frame_path(run, f, "vtu")), "vtu " + std::to_string(f));
  }
  const auto entries = pvd_entries(run + "/frames.pvd");
  const std::vector<json> lines = stats(run);
  ASSERT_EQ(entries.size(), 5u);
  for (size_t f = 0; f < entries.size(); ++f) {
    EXPECT_EQ(entries[f].second, "frames/0000" + std::to_string(f) + ".vtu");
    EXPECT_EQ(entries[f].first, lines[f]["time"].get<double>()) << f;
  }
  // Again: nothing left to do; the frames already there are kept as they are.
  ASSERT_EQ(tear("convert " + run + " --to bgeo"), 0) << err_;
  EXPECT_NE(out_.find("converted 0 frames of " + run + " to bgeo (5 already bgeo)"),
            std::string::npos)
      << out_;
}

TEST_F(ConvertCli, FramesRangeConvertsOnlyThose) {
  const std::string run = run_folder();
  ASSERT_EQ(tear("convert " + run + " --to vtu --frames 1:2"), 0) << err_;
  EXPECT_NE(out_.find("converted 2 frames"), std::string::npos) << out_;
  for (int f = 0; f <= 4; ++f)
    EXPECT_EQ(fs::exists(frame_path(run, f, "vtu")), f == 1 || f == 2) << f;
  EXPECT_EQ(pvd_entries(run + "/frames.pvd").size(), 2u);
  // From VTU back to PLY in another folder: frames are read in whatever format they are in.
  fs::create_directories(path("b/frames"));
  fs::copy_file(frame_path(run, 1, "vtu"), frame_path(path("b"), 1, "vtu"));
  ASSERT_EQ(tear("convert " + path("b") + " --to ply"), 0) << err_;
  expect_same_values(read_frame(frame_path(run, 1, "ply")),
                     read_frame(frame_path(path("b"), 1, "ply")), "vtu -> ply");
  EXPECT_EQ(tear("convert " + run + " --to bgeo --frames 7:9"), 1);
  EXPECT_NE(err_.find("tear: " + run + ": no frames in --frames 7:9\n"), std::string::npos) << err_;
  EXPECT_EQ(tear("convert " + run + " --to bgeo --frames 3:1"), 2);
  EXPECT_NE(err_.find("--frames \"3:1\""), std::string::npos) << err_;
}

TEST_F(ConvertCli, UnknownFormatAndMissingFolderFailClearly) {
  const std::string run = run_folder();
  EXPECT_EQ(tear("convert " + run + " --to stl"), 2);
  EXPECT_NE(err_.find("tear: " + run + ": unknown format \"stl\" for --to (known: ply, bgeo, vtu "
                      "for the particles; ply, obj, vtu, geo for the cloth, yarn and hair meshes)"),
            std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(frame_path(run, 0, "stl")));
  // A mesh-only format for a run of solids: nothing to write it from.
  EXPECT_EQ(tear("convert " + run + " --to obj"), 1);
  EXPECT_NE(err_.find("tear: " + run + ": obj is a format for meshes only, and the run has no "
                      "cloth, yarn or hair meshes"),
            std::string::npos)
      << err_;
  EXPECT_EQ(tear("convert " + path("missing") + " --to bgeo"), 1);
  EXPECT_NE(err_.find("tear: " + path("missing") + ": no such folder"), std::string::npos) << err_;
  fs::create_directories(path("empty"));
  EXPECT_EQ(tear("convert " + path("empty") + " --to bgeo"), 1);
  EXPECT_NE(err_.find(path("empty") + ": no frames/ folder"), std::string::npos) << err_;
  fs::create_directories(path("empty/frames"));
  EXPECT_EQ(tear("convert " + path("empty") + " --to vtu"), 1);
  EXPECT_NE(err_.find("tear: " + path("empty") + ": no frames\n"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("empty/frames.pvd")));
  EXPECT_EQ(tear("convert " + run), 2);  // --to is required
}

TEST_F(ConvertCli, RunWritesEveryFormatAndThePvdAcrossResume) {
  json s = scene();
  s["output"]["formats"] = {"ply", "bgeo", "vtu"};
  const std::string file = write_scene(s);
  ASSERT_EQ(tear("run " + file + " -o " + path("part") + " -q --frames 2"), 0) << err_;
  EXPECT_EQ(pvd_entries(path("part/frames.pvd")).size(), 3u);
  ASSERT_EQ(tear("run " + file + " -o " + path("part") + " -q --resume --frames 4"), 0) << err_;
  const auto entries = pvd_entries(path("part/frames.pvd"));
  const std::vector<json> lines = stats(path("part"));
  ASSERT_EQ(entries.size(), 5u);
  for (size_t f = 0; f < entries.size(); ++f)
    EXPECT_EQ(entries[f].first, lines[f]["time"].get<double>()) << f;
  for (int f = 0; f <= 4; ++f) {
    const PointTable ply = read_frame(frame_path(path("part"), f, "ply"));
    expect_same_values(ply, read_frame(frame_path(path("part"), f, "bgeo")), "bgeo");
    expect_same_values(ply, read_frame(frame_path(path("part"), f, "vtu")), "vtu");
  }
  // A fresh PLY-only run into the folder drops the old frames.pvd with the old frames.
  ASSERT_EQ(tear("run " + write_scene(scene(), "ply.json") + " -o " + path("part") + " -q"), 0)
      << err_;
  EXPECT_FALSE(fs::exists(path("part/frames.pvd")));
  EXPECT_FALSE(fs::exists(frame_path(path("part"), 0, "vtu")));
}

// An FEM run (docs/fem.md) through the command line: stopped after 2 frames and resumed to 4, its
// node frames, surface meshes and volume meshes are the bytes of a run that never stopped, and
// `tear convert` turns its node frames into BGEO and VTU with the PLY values.
TEST_F(ConvertCli, FemRunResumesBitIdenticallyAndConverts) {
  const json s = json::parse(R"({"dim": 3,
      "grid": {"dx": 0.05, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "slip"},
      "time": {"frame_dt": 0.02, "frames": 4, "max_dt": 0.005},
      "gravity": [0, -9.81, 0], "integrator": "implicit",
      "materials": {"jelly": {"model": "neo_hookean", "E": 2e4, "nu": 0.3, "rho": 1000}},
      "objects": [{"simulation": "fem", "mesh_size": 0.1, "material": "jelly",
                   "shape": {"type": "box", "min": [0.3, 0.3, 0.3], "max": [0.6, 0.5, 0.5]}}]})");
  const std::string file = write_scene(s, "fem.json");
  ASSERT_EQ(tear("run " + file + " -o " + path("whole") + " -q"), 0) << err_;
  ASSERT_EQ(tear("run " + file + " -o " + path("part") + " -q --frames 2"), 0) << err_;
  ASSERT_EQ(tear("run " + file + " -o " + path("part") + " -q --resume"), 0) << err_;
  for (int f = 0; f <= 4; ++f)
    for (const char* kind : {".ply", ".fem.ply", ".volume.vtu"}) {
      char name[32];
      std::snprintf(name, sizeof(name), "frames/%05d%s", f, kind);
      SCOPED_TRACE(name);
      ASSERT_TRUE(fs::exists(path("whole") + "/" + name));
      EXPECT_EQ(read_file(path("whole") + "/" + name), read_file(path("part") + "/" + name));
    }
  ASSERT_EQ(tear("convert " + path("whole") + " --to bgeo"), 0) << err_;
  ASSERT_EQ(tear("convert " + path("whole") + " --to vtu"), 0) << err_;
  for (int f = 0; f <= 4; ++f) {
    const PointTable ply = read_frame(frame_path(path("whole"), f, "ply"));
    expect_same_values(ply, read_frame(frame_path(path("whole"), f, "bgeo")), "bgeo");
    expect_same_values(ply, read_frame(frame_path(path("whole"), f, "vtu")), "vtu");
  }
}

}  // namespace
}  // namespace tear
