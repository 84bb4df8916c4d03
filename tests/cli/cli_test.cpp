// End-to-end tests of the `tear` executable: outputs, determinism, resume, bad input.
#include "cli_fixture.h"
#include "tear/io/atomic_file.h"
#include "tear/io/ply.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>

#include <sys/wait.h>

namespace tear {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST_F(Cli, RunWritesTheDocumentedOutputs) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
  EXPECT_NE(out_.find("wrote 4 frames"), std::string::npos) << out_;
  EXPECT_EQ(err_, "");  // --quiet: no progress
  EXPECT_EQ(count_frames(path("run")), 5);
  for (int f = 0; f <= 4; ++f)
    EXPECT_TRUE(fs::exists(path("run/frames/0000" + std::to_string(f) + ".ply"))) << f;
  EXPECT_TRUE(fs::exists(path("run/checkpoints/latest.bin")));
  // scene.json is the resolved scene: defaults filled in.
  const json resolved = json::parse(read_file(path("run/scene.json")));
  EXPECT_EQ(resolved["transfer"], "apic");
  EXPECT_EQ(resolved["time"]["cfl"], 0.4);
  // Frames: the documented columns, rows sorted by id.
  const PointTable t = decode_ply(read_file(path("run/frames/00004.ply")));
  for (const char* c :
       {"id", "x", "y", "z", "vx", "vy", "vz", "damage", "material", "fx", "fy", "fz"})
    EXPECT_TRUE(t.has(c)) << c;
  ASSERT_GT(t.count, 200u);
  for (size_t i = 0; i < t.count; ++i) ASSERT_EQ(t.column("id")[i], double(i));
  EXPECT_EQ(t.column("z"), std::vector<double>(t.count, 0.0));
}

TEST_F(Cli, StatsHaveOneLinePerFrameWithTheDocumentedKeys) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
  const std::vector<json> lines = stats(path("run"));
  ASSERT_EQ(lines.size(), 5u);
  for (size_t f = 0; f < lines.size(); ++f) {
    for (const char* k : {"frame", "time", "steps", "dt_min", "dt_max", "steps_redone",
                          "particles", "mass", "momentum", "angular_momentum", "kinetic_energy",
                          "elastic_energy", "max_damage", "mean_damage", "damaged_fraction",
                          "wall_s"})
      EXPECT_TRUE(lines[f].contains(k)) << k;
    EXPECT_EQ(lines[f]["frame"], int(f));
    EXPECT_EQ(lines[f]["particles"], lines[0]["particles"]);
    EXPECT_EQ(lines[f]["mass"], lines[0]["mass"]);  // exactly: particles carry fixed mass
    EXPECT_EQ(lines[f]["momentum"].size(), 3u);
    EXPECT_EQ(lines[f]["angular_momentum"].size(), 3u);
  }
  EXPECT_GT(lines[0]["mass"].get<double>(), 0);
  EXPECT_NEAR(lines[4]["time"].get<double>(), 0.08, 1e-15);  // steps land on frame times
  EXPECT_GT(lines[4]["steps"].get<int>(), 0);
}

TEST_F(Cli, ProgressGoesToStderrAndTheSummaryToStdout) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("run")), 0) << err_;
  // Not a terminal: plain lines, no carriage returns; the last one reports the last frame.
  EXPECT_NE(err_.find("frame 4/4  t=0.080s  steps/s "), std::string::npos) << err_;
  EXPECT_NE(err_.find("ETA"), std::string::npos) << err_;
  EXPECT_EQ(err_.find('\r'), std::string::npos) << err_;
  EXPECT_EQ(out_.find("frame 4/4"), std::string::npos) << out_;
  EXPECT_NE(out_.find("wrote 4 frames ("), std::string::npos) << out_;
  EXPECT_NE(out_.find(" to " + path("run") + " in "), std::string::npos) << out_;
}

TEST_F(Cli, OutputIsBitIdenticalForOneAndTwoThreads) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("t1") + " -q --threads 1"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("t2") + " -q --threads 2"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("t2b") + " -q --threads 2"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("t0") + " -q --threads 0"), 0) << err_;
  for (int f = 0; f <= 4; ++f) {
    const std::string name = "/frames/0000" + std::to_string(f) + ".ply";
    EXPECT_EQ(read_file(path("t1") + name), read_file(path("t2") + name)) << name;
    EXPECT_EQ(read_file(path("t2") + name), read_file(path("t2b") + name)) << name;
    EXPECT_EQ(read_file(path("t1") + name), read_file(path("t0") + name)) << name;
  }
  EXPECT_EQ(read_file(path("t1/checkpoints/latest.bin")),
            read_file(path("t2/checkpoints/latest.bin")));
  // The comparison means something: the particles moved.
  EXPECT_NE(read_file(path("t1/frames/00000.ply")), read_file(path("t1/frames/00004.ply")));
}

TEST_F(Cli, ResumedRunMatchesAnUninterruptedOne) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("full") + " -q"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --frames 2"), 0) << err_;
  EXPECT_EQ(count_frames(path("part")), 3);
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " --resume --frames 4"), 0) << err_;
  EXPECT_NE(err_.find("resuming"), std::string::npos) << err_;
  EXPECT_EQ(count_frames(path("part")), 5);
  EXPECT_EQ(read_file(path("full/frames/00004.ply")), read_file(path("part/frames/00004.ply")));
  EXPECT_EQ(read_file(path("full/checkpoints/latest.bin")),
            read_file(path("part/checkpoints/latest.bin")));
  EXPECT_EQ(json::parse(read_file(path("part/scene.json")))["time"]["frames"], 4);
  const std::vector<json> a = stats(path("full")), b = stats(path("part"));
  ASSERT_EQ(b.size(), 5u);
  for (size_t f = 0; f < a.size(); ++f) {
    EXPECT_EQ(a[f]["frame"], b[f]["frame"]) << f;
    EXPECT_EQ(a[f]["momentum"], b[f]["momentum"]) << f;
    EXPECT_EQ(a[f]["steps"], b[f]["steps"]) << f;
  }
  // Resuming a finished run is not an error and changes nothing.
  EXPECT_EQ(tear("run " + s + " -o " + path("part") + " --resume --frames 3"), 0) << err_;
  EXPECT_NE(out_.find("already complete"), std::string::npos) << out_;
  EXPECT_EQ(json::parse(read_file(path("part/scene.json")))["time"]["frames"], 4);
  // Resuming with a changed scene, or where nothing ran, is.
  EXPECT_EQ(tear("run " + s + " -o " + path("part") + " --resume --set materials.jelly.E=600"), 1);
  EXPECT_NE(err_.find(path("part") + "/scene.json: scene differs from " + s +
                      " at materials.jelly.E (was 500"),
            std::string::npos)
      << err_;
  EXPECT_NE(err_.find("now 600"), std::string::npos) << err_;
  EXPECT_EQ(tear("run " + s + " -o " + path("part") + " --resume --set objects.0.ppc=9"), 1);
  EXPECT_NE(err_.find(" at objects[0].ppc (was 4"), std::string::npos) << err_;
  // Keys that change no result may change: the description, render, checkpoint_every.
  ASSERT_EQ(tear("run " + s + " -o " + path("part") +
                 " -q --resume --frames 5 --set output.checkpoint_every=2 --set "
                 "description=resumed --set render.width=64"),
            0)
      << err_;
  EXPECT_EQ(count_frames(path("part")), 6);
  EXPECT_EQ(json::parse(read_file(path("part/scene.json")))["output"]["checkpoint_every"], 2);
  EXPECT_EQ(tear("run " + s + " -o " + path("nothing_here") + " --resume"), 1);
  EXPECT_NE(err_.find("no earlier run"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("nothing_here")));
}

// Checkpoints carry a checksum; a resume whose latest checkpoint is damaged (a flipped bit, cut
// short) or missing (a kill between setting the last one aside and writing the new one) falls
// back to checkpoints/previous.bin, says so, and still ends bit-identical to an uninterrupted
// run. Where both are bad, or the format version differs, it is refused with the reasons.
TEST_F(Cli, DamagedCheckpointFallsBackToThePreviousOne) {
  const std::string s = write_scene(scene());  // a checkpoint every frame
  ASSERT_EQ(tear("run " + s + " -o " + path("full") + " -q"), 0) << err_;
  const std::string full = read_file(path("full/frames/00004.ply"));
  const auto interrupted = [&](const std::string& name) {
    EXPECT_EQ(tear("run " + s + " -o " + path(name) + " -q --frames 3"), 0) << err_;
    EXPECT_TRUE(fs::exists(path(name + "/checkpoints/previous.bin")));
    return path(name + "/checkpoints/latest.bin");
  };
  const auto flip_bit = [](const std::string& file) {
    std::string b = read_file(file);
    b[b.size() / 2] ^= 4;
    write_file_atomic(file, b);
  };
  const auto resumes_from_previous = [&](const std::string& name, const std::string& reason) {
    ASSERT_EQ(tear("run " + s + " -o " + path(name) + " --resume"), 0) << err_;
    EXPECT_NE(err_.find(reason), std::string::npos) << err_;
    EXPECT_NE(err_.find("resuming from " + path(name) + "/checkpoints/previous.bin (frame 2)"),
              std::string::npos)
        << err_;
    EXPECT_EQ(read_file(path(name + "/frames/00004.ply")), full) << name;
  };
  flip_bit(interrupted("flipped"));
  resumes_from_previous("flipped", "latest.bin: damaged: its checksum does not match");
  EXPECT_TRUE(fs::exists(path("flipped/checkpoints/damaged.bin")));
  const std::string cut = interrupted("cut");
  write_file_atomic(cut, read_file(cut).substr(0, 1000));
  resumes_from_previous("cut", "latest.bin: damaged");
  fs::remove(interrupted("killed"));
  resumes_from_previous("killed", "latest.bin");

  const std::string both = interrupted("both");
  flip_bit(both);
  flip_bit(path("both/checkpoints/previous.bin"));
  EXPECT_EQ(tear("run " + s + " -o " + path("both") + " --resume"), 1);
  EXPECT_NE(err_.find("latest.bin: damaged"), std::string::npos) << err_;
  EXPECT_NE(err_.find("previous.bin: damaged"), std::string::npos) << err_;
  const std::string old = interrupted("old");
  fs::remove(path("old/checkpoints/previous.bin"));
  std::string b = read_file(old);
  b[7] = '8';
  write_file_atomic(old, b);
  EXPECT_EQ(tear("run " + s + " -o " + path("old") + " --resume"), 1);
  EXPECT_NE(err_.find("checkpoint format version 8, this tear reads versions A and B"),
            std::string::npos)
      << err_;
  write_file_atomic(old, "not a checkpoint at all");
  EXPECT_EQ(tear("run " + s + " -o " + path("old") + " --resume"), 1);
  EXPECT_NE(err_.find("latest.bin: not a tear checkpoint"), std::string::npos) << err_;
}

TEST_F(Cli, SetAndFramesOverrideTheScene) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("o") + " -q --frames 2 --set materials.jelly.E=750"
                 " --set 'gravity=[0,-1]' --set transfer=pic"),
            0)
      << err_;
  const json resolved = json::parse(read_file(path("o/scene.json")));
  EXPECT_EQ(resolved["materials"]["jelly"]["E"], 750);
  EXPECT_EQ(resolved["gravity"], json::parse("[0,-1]"));
  EXPECT_EQ(resolved["transfer"], "pic");  // not JSON: taken as a string
  EXPECT_EQ(resolved["time"]["frames"], 2);
  EXPECT_EQ(count_frames(path("o")), 3);
  EXPECT_TRUE(fs::exists(path("o/frames/00002.ply")));
  EXPECT_EQ(stats(path("o")).size(), 3u);
  // check applies --set too.
  ASSERT_EQ(tear("check " + s + " --set materials.jelly.E=750"), 0) << err_;
  EXPECT_NE(out_.find("E 750"), std::string::npos) << out_;
}

TEST_F(Cli, BadInputFailsWithAReasonAndWritesNothing) {
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
    EXPECT_EQ(err_.rfind("tear: ", 0), 0u) << err_;
    EXPECT_NE(err_.find("bad.json"), std::string::npos) << err_;
    EXPECT_NE(err_.find(expected), std::string::npos) << err_;
    EXPECT_EQ(err_.find('\n'), err_.size() - 1) << "one line: " << err_;
    EXPECT_FALSE(fs::exists(path("never"))) << expected;
    EXPECT_EQ(tear("check " + s), 1);
    EXPECT_NE(err_.find(expected), std::string::npos) << err_;
  }
  EXPECT_EQ(tear("run " + path("missing.json") + " -o " + path("never")), 1);
  EXPECT_NE(err_.find("missing.json"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("never")));
  // The same through --set: an unknown key and a bad value.
  const std::string s = write_scene(scene());
  EXPECT_EQ(tear("run " + s + " -o " + path("never") + " --set materials.jelly.nuu=1"), 1);
  EXPECT_NE(err_.find("materials.jelly.nuu"), std::string::npos) << err_;
  EXPECT_EQ(tear("run " + s + " -o " + path("never") + " --set materials.jelly.E=-5"), 1);
  EXPECT_NE(err_.find("materials.jelly.E"), std::string::npos) << err_;
  EXPECT_NE(err_.find("scene.json"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("never")));
}

TEST_F(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(tear(""), 2);
  EXPECT_EQ(tear("run"), 2);
  EXPECT_EQ(tear("run x.json"), 2);  // no -o
  EXPECT_EQ(tear("run --threads -3 x.json -o y"), 2);
  EXPECT_EQ(tear("frobnicate"), 2);
  EXPECT_EQ(tear("--help"), 0);
  for (const char* sub : {"run", "check", "info", "bench"})
    EXPECT_NE(out_.find(sub), std::string::npos) << sub;
  EXPECT_EQ(tear("run --help"), 0);
  for (const char* opt : {"--out", "--threads", "--frames", "--set", "--quiet", "--resume"})
    EXPECT_NE(out_.find(opt), std::string::npos) << opt;
  EXPECT_EQ(tear("--version"), 0);
  EXPECT_EQ(out_.rfind("tear ", 0), 0u) << out_;
}

TEST_F(Cli, InfoAndQuickBench) {
  EXPECT_EQ(tear("info"), 0) << err_;
  for (const char* k : {"precision", "asserts", "compiler", "simd", "eigen", "onetbb", "threads",
                        "embree", "libpng", "openvdb", "ffmpeg"})
    EXPECT_NE(out_.find(k), std::string::npos) << k;
  // The build's vector instructions: SSE2 at least on x86-64; FMA never (its rounding differs
  // between Eigen's scalar and vector paths: CMakeLists.txt, TEAR_NATIVE).
#if defined(__x86_64__)
  EXPECT_NE(out_.find("SSE2"), std::string::npos) << out_;
#endif
  EXPECT_EQ(out_.find("FMA"), std::string::npos) << out_;
  // stdout is exactly one JSON object; notes go to stderr.
  ASSERT_EQ(tear("bench --quick --threads-list 1,2"), 0) << err_;
  const json b = json::parse(out_);
  for (const char* k : {"evaluations", "qr_aniso", "fixed_corotated"})
    EXPECT_TRUE(b["stress"].contains(k)) << k;
  EXPECT_EQ(b["stress"]["evaluations"], 100000);
  EXPECT_GT(b["stress"]["speedup_qr_over_fixed_corotated"].get<double>(), 0.0);
  ASSERT_EQ(b["step"].size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(b["step"][i]["threads"], i + 1);
    EXPECT_EQ(b["step"][i]["steps"], 5);
    EXPECT_GT(b["step"][i]["particle_steps_per_s"].get<double>(), 0);
    EXPECT_GT(b["step"][i]["particles"].get<long>(), 10000);
    EXPECT_TRUE(b["step"][i].contains("phase_s"));
  }
  for (const char* k : {"none", "explicit", "implicit"})
    EXPECT_GT(b["damage"][k]["s_per_step"].get<double>(), 0) << k;
  EXPECT_GE(b["damage"]["implicit"]["damage_iterations_per_solve"].get<double>(), 1.0);
  EXPECT_GT(b["damage"]["implicit"]["cost_vs_none"].get<double>(), 1.0);
}

// A fibered block pulled apart by two grips, with implicit damage: it cracks.
json tearing_scene() {
  return json::parse(R"({
    "name": "cli_tear", "dim": 2,
    "grid": { "dx": 0.03125, "domain_min": [0, 0], "domain_max": [1, 1] },
    "time": { "frame_dt": 0.05, "frames": 4 },
    "damage": { "solver": "implicit" },
    "materials": { "m": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2,
                          "fiber_scale": [10],
                          "damage": { "sigma_c": 3, "eta": 0.05, "alpha": -1 } } },
    "objects": [ { "shape": { "type": "box", "min": [0.3, 0.3], "max": [0.7, 0.7] },
                   "material": "m", "ppc": 4, "sampling": "grid",
                   "fibers": { "type": "constant", "a1": [1, 1] } } ],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0.2, 0.64], "max": [0.8, 0.75] },
        "velocity": [0, 0.4] },
      { "type": "sticky", "shape": { "type": "box", "min": [0.2, 0.25], "max": [0.8, 0.36] },
        "velocity": [0, -0.4] } ],
    "output": { "every": 1, "checkpoint_every": 1 }
  })");
}

// check prints where the damageable material starts to crack: across the fibers first.
TEST_F(Cli, CheckPrintsTheCrackOnsetStretch) {
  const std::string s = write_scene(tearing_scene());
  ASSERT_EQ(tear("check " + s), 0) << err_;
  const std::string key = "cracks start at a uniaxial stretch of ";
  const size_t at = out_.find(key);
  ASSERT_NE(at, std::string::npos) << out_;
  std::istringstream line(out_.substr(at + key.size()));
  double across = 0, along = 0;
  std::string word;
  line >> across >> word >> word >> word >> along;
  EXPECT_GT(across, 1.0) << out_;
  EXPECT_LT(across, 1.2) << out_;  // sigma_c 3 against moduli ~40: a few percent
  EXPECT_GT(along, across) << out_;
  EXPECT_EQ(out_.find("surface_anisotropy"), std::string::npos) << out_;  // the paper's term
  // An anisotropic crack surface is said, with its weights.
  json aniso = tearing_scene();
  aniso["damage"]["solver"] = "explicit";
  aniso["materials"]["m"]["damage"]["surface_anisotropy"] = 30;
  ASSERT_EQ(tear("check " + write_scene(aniso)), 0) << err_;
  EXPECT_NE(out_.find("alpha [-1, 0], surface_anisotropy [30, 0]; cracks start"),
            std::string::npos)
      << out_;
  // The scene-wide settings: the solver, l0 and whether crack fields split the grid.
  EXPECT_NE(out_.find("cracking   explicit damage solver, l0 "), std::string::npos) << out_;
  EXPECT_NE(out_.find(", one velocity field (the paper's"), std::string::npos) << out_;
  // The pointer to the sharp-crack recipe: for fibered damage with the paper's method only.
  const std::string recipe = "Cracks that follow the fibers and stay sharp";
  EXPECT_EQ(out_.find(recipe), std::string::npos) << out_;  // surface_anisotropy is set
  json paper = tearing_scene();
  paper["damage"]["solver"] = "explicit";
  ASSERT_EQ(tear("check " + write_scene(paper)), 0) << err_;
  EXPECT_NE(out_.find(recipe), std::string::npos) << out_;
  paper["materials"]["m"]["damage"]["alpha"] = 0;
  ASSERT_EQ(tear("check " + write_scene(paper)), 0) << err_;
  EXPECT_EQ(out_.find(recipe), std::string::npos) << out_;  // isotropic damage
  aniso["damage"]["split_fields"] = true;
  aniso["damage"]["split_damage"] = 0.3;
  ASSERT_EQ(tear("check " + write_scene(aniso)), 0) << err_;
  EXPECT_NE(out_.find(", crack fields (a node splits at damage 0.3)"), std::string::npos)
      << out_;
}

TEST_F(Cli, ImplicitDamageRecordsSolverFiguresAndResumesBitIdentically) {
  const std::string s = write_scene(tearing_scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("full") + " -q"), 0) << err_;
  EXPECT_EQ(err_.find("warning"), std::string::npos) << err_;
  const std::vector<json> a = stats(path("full"));
  ASSERT_EQ(a.size(), 5u);
  EXPECT_GT(a.back()["max_damage"].get<double>(), 0.9);
  long solves = 0, iterations = 0;
  for (const json& f : a) {
    for (const char* k : {"damage_solves", "damage_iterations", "damage_iterations_max",
                          "damage_unconverged", "damage_change"})
      EXPECT_TRUE(f.contains(k)) << k;
    solves += f["damage_solves"].get<long>();
    iterations += f["damage_iterations"].get<long>();
    EXPECT_EQ(f["damage_unconverged"], 0);
    EXPECT_LE(f["damage_change"].get<double>(), 1e-6);
  }
  EXPECT_GT(solves, 0);
  EXPECT_LE(iterations, 3 * solves);
  // Resume half way: same bits.
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --frames 2"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --resume --frames 4"), 0) << err_;
  EXPECT_EQ(read_file(path("full/frames/00004.ply")), read_file(path("part/frames/00004.ply")));
  // A solve that cannot converge is reported once on stderr, and counted.
  ASSERT_EQ(tear("run " + s + " -o " + path("capped") +
                 " -q --set damage.max_iterations=1 --set damage.tolerance=1e-14"),
            0)
      << err_;
  EXPECT_NE(err_.find("warning: frame"), std::string::npos) << err_;
  EXPECT_EQ(err_.find("warning", err_.find("warning") + 1), std::string::npos) << err_;
  EXPECT_GT(stats(path("capped")).back()["damage_unconverged"].get<long>(), 0);
}

// Inextensible ropes end to end (examples/hanging_disk_2d.json, coarser): stats.jsonl carries
// the solve's figures, frames the fiber_tension column, the Cholesky preconditioner needs one
// or two CG iterations a step (Jacobi many more), and a resumed run gives the same bits.
TEST_F(Cli, InextensibleRopesRecordTheirSolveAndResumeBitIdentically) {
  const std::string scene =
      (std::filesystem::path(TEAR_SOURCE_DIR) / "examples" / "hanging_disk_2d.json").string();
  const std::string coarse = " -q --set grid.dx=0.015625 --set time.frames=4";
  ASSERT_EQ(tear("run " + scene + " -o " + path("full") + coarse), 0) << err_;
  const std::vector<json> a = stats(path("full"));
  ASSERT_EQ(a.size(), 5u);
  long steps = 0, iterations = 0;
  for (const json& f : a) {
    for (const char* k : {"inextensibility_iterations", "inextensibility_iterations_max",
                          "inextensibility_residual", "inextensibility_unconverged"})
      EXPECT_TRUE(f.contains(k)) << k;
    steps += f["steps"].get<long>();
    iterations += f["inextensibility_iterations"].get<long>();
    EXPECT_EQ(f["inextensibility_unconverged"], 0);
    EXPECT_LE(f["inextensibility_residual"].get<double>(), 1e-6);
    EXPECT_LE(f["inextensibility_iterations_max"].get<int>(), 2);
  }
  EXPECT_GT(steps, 0);
  EXPECT_GE(iterations, steps);
  EXPECT_NE(read_file(path("full/frames/00004.ply")).find("property float fiber_tension"),
            std::string::npos);
  ASSERT_EQ(tear("run " + scene + " -o " + path("jacobi") + coarse +
                 " --set inextensibility.preconditioner=jacobi --frames 1"),
            0)
      << err_;
  const json j = stats(path("jacobi")).back();
  EXPECT_GT(j["inextensibility_iterations"].get<long>(), 20 * j["steps"].get<long>());
  ASSERT_EQ(tear("run " + scene + " -o " + path("part") + coarse + " --frames 2"), 0) << err_;
  ASSERT_EQ(tear("run " + scene + " -o " + path("part") + coarse + " --resume --frames 4"), 0)
      << err_;
  EXPECT_EQ(read_file(path("full/frames/00004.ply")), read_file(path("part/frames/00004.ply")));
}

// The implicit integrator's auto preconditioner switches to multigrid once a solve stalls, says
// so in stats.jsonl, and a run resumed after the switch takes the same path (the switch is in
// the checkpoint): the same bits.
TEST_F(Cli, ImplicitAutoPreconditionerSwitchesAndResumesBitIdentically) {
  const std::string scene =
      (std::filesystem::path(TEAR_SOURCE_DIR) / "bench" / "scenes" / "stiff_cantilever_2d.json")
          .string();
  const std::string coarse =
      " -q --set grid.dx=0.015625 --set time.max_dt=5e-4 --set implicit.multigrid_after=5";
  ASSERT_EQ(tear("run " + scene + " -o " + path("full") + coarse + " --frames 4"), 0) << err_;
  const std::vector<json> a = stats(path("full"));
  ASSERT_EQ(a.size(), 5u);
  for (size_t f = 1; f < a.size(); ++f) {
    EXPECT_GT(a[f]["cg_multigrid_solves"].get<long>(), 0) << "frame " << f;
    EXPECT_EQ(a[f]["cg_multigrid_solves"], a[f]["newton_iterations"]) << "frame " << f;
    EXPECT_EQ(a[f]["newton_unconverged"], 0);
  }
  ASSERT_EQ(tear("run " + scene + " -o " + path("jacobi") + coarse +
                 " --frames 1 --set implicit.preconditioner=jacobi"),
            0)
      << err_;
  const json j = stats(path("jacobi")).back();
  EXPECT_EQ(j["cg_multigrid_solves"], 0);
  EXPECT_GT(j["cg_iterations"].get<long>(), 2 * a[1]["cg_iterations"].get<long>());
  ASSERT_EQ(tear("run " + scene + " -o " + path("part") + coarse + " --frames 2"), 0) << err_;
  ASSERT_EQ(tear("run " + scene + " -o " + path("part") + coarse + " --resume --frames 4"), 0)
      << err_;
  EXPECT_EQ(read_file(path("full/frames/00004.ply")), read_file(path("part/frames/00004.ply")));
}

// The implicit bone demo (Table 1's femur stiffness, 45x the explicit step): every Newton solve
// of its first half-frame converges, in at most three iterations. Measured by |g_i| / m_i alone,
// nodes the femur barely reaches (1e-8 of a particle's mass) held Newton's residual at 5x its
// tolerance for all 20 iterations of a few steps (and 100 when allowed).
TEST_F(Cli, ImplicitBoneNewtonConverges) {
  const std::string scene = (std::filesystem::path(TEAR_SOURCE_DIR) / "examples" / "paper" /
                             "fig24_bone_bend_implicit.json")
                                .string();
  ASSERT_EQ(tear("run " + scene + " -o " + path("bone") +
                 " -q --frames 1 --set time.frame_dt=0.010416666666666666"),
            0)
      << err_;
  const json j = stats(path("bone")).back();
  EXPECT_EQ(j["steps"], 42);
  EXPECT_EQ(j["newton_unconverged"], 0);
  EXPECT_LE(j["newton_iterations_max"].get<int>(), 3);
}

// Crack fields: a run resumed half way gives the same bits (the partition is recomputed every
// step from the state; its scratch is not part of a checkpoint), and they change the result.
TEST_F(Cli, CrackFieldsResumeBitIdentically) {
  const std::string s = write_scene(tearing_scene());
  const std::string split = " --set damage.split_fields=true --set damage.solver=explicit";
  ASSERT_EQ(tear("run " + s + " -o " + path("full") + " -q" + split), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("one") + " -q --set damage.solver=explicit"), 0)
      << err_;
  EXPECT_GT(stats(path("full")).back()["max_damage"].get<double>(), 0.9);
  EXPECT_NE(read_file(path("full/frames/00004.ply")), read_file(path("one/frames/00004.ply")));
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --frames 2" + split), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --resume --frames 4" + split), 0)
      << err_;
  EXPECT_EQ(read_file(path("full/frames/00004.ply")), read_file(path("part/frames/00004.ply")));
  EXPECT_EQ(read_file(path("full/checkpoints/latest.bin")),
            read_file(path("part/checkpoints/latest.bin")));
}

}  // namespace
}  // namespace tear

namespace tear {

// Every shipped scene, examples/ and examples/paper/, passes `tear check`; a paper demo's
// description is printed under its name.
TEST_F(Cli, EveryExampleChecks) {
  namespace fs = std::filesystem;
  int checked = 0;
  for (const auto &e :
       fs::recursive_directory_iterator(fs::path(TEAR_SOURCE_DIR) / "examples")) {
    if (e.path().extension() != ".json") continue;
    SCOPED_TRACE(e.path().string());
    EXPECT_EQ(tear("check " + e.path().string()), 0) << err_;
    // An FEM scene counts its nodes (docs/fem.md).
    EXPECT_TRUE(out_.find("\nparticles  ") != std::string::npos ||
                out_.find("\nnodes      ") != std::string::npos)
        << out_;
    if (e.path().parent_path().filename() == "paper") {
      EXPECT_NE(out_.find("\n           AnisoMPM paper Fig."), std::string::npos) << out_;
    }
    ++checked;
  }
  EXPECT_GE(checked, 30);
}

// --resolution K divides dx and max_dt by K, for check and run alike, and is refused when not
// positive.
TEST_F(Cli, ResolutionRefinesTheGrid) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("check " + s + " --resolution 2"), 0) << err_;
  EXPECT_NE(out_.find("dx 0.015625,"), std::string::npos) << out_;
  ASSERT_EQ(tear("run " + s + " -o " + path("r") + " -q --frames 1 --resolution 2"), 0) << err_;
  const json resolved = json::parse(read_file(path("r/scene.json")));
  EXPECT_EQ(resolved["grid"]["dx"], 0.015625);
  EXPECT_EQ(tear("run " + s + " -o " + path("never") + " --resolution 0"), 2);  // usage error
  EXPECT_FALSE(std::filesystem::exists(path("never")));
}

}  // namespace tear
