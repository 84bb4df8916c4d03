// Runs that survive (docs/long-runs.md): a stop on SIGINT/SIGTERM writes a checkpoint and
// resumes bit-identically; failed writes stop the run with the path and leave no partial file;
// an unstable run names its particle and exits 3; --max-memory refuses a run too large; a
// resume continues explicit-damage, implicit-damage and plastic runs bit-identically.
#include "cli_fixture.h"
#include "tear/io/atomic_file.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace tear {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class LongRun : public Cli {
 protected:
  // Every file under DIR/frames (and DIR/checkpoints/latest.bin) equals REF's; stats lines
  // equal except wall_s. `frames`: the frames both must have.
  void expect_same_run(const std::string& ref, const std::string& run, int frames) {
    for (int f = 0; f <= frames; ++f) {
      const std::string name = "/frames/" + std::string(5 - std::to_string(f).size(), '0') +
                               std::to_string(f) + ".ply";
      ASSERT_TRUE(fs::exists(run + name)) << run + name;
      EXPECT_EQ(read_file(ref + name), read_file(run + name)) << name;
    }
    EXPECT_EQ(read_file(ref + "/checkpoints/latest.bin"), read_file(run + "/checkpoints/latest.bin"));
    std::vector<json> a = stats(ref), b = stats(run);
    ASSERT_EQ(a.size(), b.size());
    for (size_t f = 0; f < a.size(); ++f) {
      a[f].erase("wall_s");
      b[f].erase("wall_s");
      EXPECT_EQ(a[f], b[f]) << "frame " << f;
    }
  }

  // No ".NAME.tmp.PID" temporaries (or any other hidden file) left in the run's folders.
  void expect_no_temporaries(const std::string& run) {
    for (const char* sub : {"", "/frames", "/checkpoints"}) {
      if (!fs::exists(run + sub)) continue;
      for (const auto& e : fs::directory_iterator(run + sub))
        EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
    }
  }

  // Starts `tear ARGS` in the background, sends SIGNAL once DIR/stats.jsonl has `lines` lines,
  // and returns tear's exit code (stderr in err_).
  int tear_signalled(const std::string& args, const std::string& run, const char* signal,
                     int lines) {
    const std::string err = path("stderr.txt"), rc = path("rc.txt");
    const std::string cmd =
        "sh -c '" + std::string(TEAR_CLI) + " " + args + " > /dev/null 2> " + err +
        " & p=$!; while ! [ -f " + run + "/stats.jsonl ] || [ $(wc -l < " + run +
        "/stats.jsonl) -lt " + std::to_string(lines) +
        " ]; do kill -0 $p 2> /dev/null || break; sleep 0.005; done; kill -" + signal +
        " $p; wait $p; echo $? > " + rc + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    err_ = read_file(err);
    return std::stoi(read_file(rc));
  }

  // The fixture's disk, at twice the resolution so that a frame takes a while.
  std::string slow_scene() {
    json j = scene();
    j["grid"]["dx"] = 0.015625;
    j["time"]["frames"] = 400;
    return write_scene(j);
  }
};

TEST_F(LongRun, StopSignalsWriteACheckpointAndResumeBitIdentically) {
  const std::string s = slow_scene();
  ASSERT_EQ(tear("run " + s + " -o " + path("ref") + " -q --frames 10"), 0) << err_;
  for (const char* signal : {"INT", "TERM"}) {
    const std::string run = path(std::string("run_") + signal);
    const int code =
        tear_signalled("run " + s + " -o " + run + " -q --set output.checkpoint_every=100", run,
                       signal, 3);
    ASSERT_EQ(code, std::string(signal) == "INT" ? 130 : 143) << err_;
    EXPECT_NE(err_.find(std::string("tear: stopped by SIG") + signal), std::string::npos) << err_;
    EXPECT_NE(err_.find("checkpoint written: continue with --resume"), std::string::npos);
    // checkpoint_every 100: the only checkpoint is the one the stop wrote, mid-frame or at
    // the frame it stopped after.
    ASSERT_TRUE(fs::exists(run + "/checkpoints/latest.bin"));
    const int done = int(stats(run).size()) - 1;
    ASSERT_LT(done, 10) << "the stop came too late to test a resume";
    expect_no_temporaries(run);
    ASSERT_EQ(tear("run " + s + " -o " + run + " --frames 10 --resume"), 0) << err_;
    EXPECT_NE(err_.find("resuming " + run + " at frame " + std::to_string(done)),
              std::string::npos)
        << err_;
    expect_same_run(path("ref"), run, 10);
  }
}

TEST_F(LongRun, FailedWritesStopTheRunNamingThePathAndLeaveNoPartialFile) {
  const std::string s = write_scene(scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("ref") + " -q --frames 6"), 0) << err_;
  // The disk fills while frame 3 is written: the error names the file and the reason, the
  // frame is absent (no partial file, no temporary), the checkpoint of frame 2 stays.
  const std::string run = path("run");
  ASSERT_EQ(std::system(("TEAR_TEST_FAIL_WRITE=frames/00003.ply " + std::string(TEAR_CLI) +
                         " run " + s + " -o " + run + " -q --frames 6 2> " + path("err.txt"))
                            .c_str()) >> 8,
            1);
  err_ = read_file(path("err.txt"));
  EXPECT_NE(err_.find("tear: " + run + "/frames/00003.ply: cannot write: No space left on device"),
            std::string::npos)
      << err_;
  EXPECT_NE(err_.find("the last good checkpoint (frame 2, t = 0.040s) is kept"),
            std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(run + "/frames/00003.ply"));
  expect_no_temporaries(run);
  // A checkpoint that cannot be written (permission denied) leaves the one before it.
  ASSERT_EQ(std::system(("TEAR_TEST_FAIL_WRITE=checkpoints/latest.bin,EACCES " +
                         std::string(TEAR_CLI) + " run " + s + " -o " + run +
                         " -q --frames 6 --resume 2> " + path("err.txt"))
                            .c_str()) >> 8,
            1);
  err_ = read_file(path("err.txt"));
  EXPECT_NE(err_.find(run + "/checkpoints/latest.bin: cannot write: Permission denied"),
            std::string::npos)
      << err_;
  EXPECT_TRUE(fs::exists(run + "/checkpoints/previous.bin"));
  expect_no_temporaries(run);
  // A stats.jsonl that cannot be written stops the run too.
  EXPECT_EQ(std::system(("TEAR_TEST_FAIL_WRITE=stats.jsonl " + std::string(TEAR_CLI) + " run " +
                         s + " -o " + run + " -q --frames 6 --resume 2> " + path("err.txt"))
                            .c_str()) >> 8,
            1);
  EXPECT_NE(read_file(path("err.txt")).find("stats.jsonl: cannot write: No space left on device"),
            std::string::npos);
  expect_no_temporaries(run);
  // Once the disk is back, --resume ends where an uninterrupted run does.
  ASSERT_EQ(tear("run " + s + " -o " + run + " -q --frames 6 --resume"), 0) << err_;
  expect_same_run(path("ref"), run, 6);
}

TEST_F(LongRun, AParticleLeavingTheDomainStopsTheRunWithItsIdAndExitCode3) {
  // No walls: the disk flies out through the right face.
  json j = scene();
  j["grid"]["walls"] = "none";
  j["gravity"] = {0, 0};
  j["boundaries"] = json::array();
  j["objects"][0]["velocity"] = {8, 0};
  j["time"]["frames"] = 20;
  const std::string s = write_scene(j);
  EXPECT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 3) << err_;
  EXPECT_NE(err_.find("tear: the run stopped in frame "), std::string::npos)
      << err_;
  EXPECT_NE(err_.find("(material jelly) left the domain at x (0.96875"), std::string::npos)
      << err_;
  EXPECT_NE(err_.find("enlarge grid.domain_min/domain_max"), std::string::npos) << err_;
  EXPECT_NE(err_.find("the last good checkpoint (frame "), std::string::npos) << err_;
  // An object that starts within a cell of the edge is refused before anything is written.
  j["objects"][0]["shape"]["center"] = {0.5, 0.15};
  EXPECT_EQ(tear("run " + write_scene(j) + " -o " + path("edge") + " -q"), 1) << err_;
  EXPECT_NE(err_.find("(material jelly) starts outside the domain at x ("), std::string::npos)
      << err_;
  EXPECT_NE(err_.find("must start inside the grid's domain less one cell"), std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(path("edge")));
}

// A NaN that appears in a step (injected by the test hook) stops the run in that step with
// exit code 3, naming the particle; the frames and checkpoint before it stay.
TEST_F(LongRun, ANanStopsTheRunInItsStepWithExitCode3) {
  const std::string s = write_scene(scene());
  const std::string run = path("run");
  EXPECT_EQ(std::system(("TEAR_TEST_INJECT_NAN=150,17 " + std::string(TEAR_CLI) + " run " + s +
                         " -o " + run + " -q 2> " + path("err.txt"))
                            .c_str()) >> 8,
            3);
  err_ = read_file(path("err.txt"));
  EXPECT_NE(err_.find("tear: the simulation became unstable in frame "), std::string::npos)
      << err_;
  EXPECT_NE(err_.find(", step 150 (dt "), std::string::npos) << err_;
  EXPECT_NE(err_.find("particle 17 (material jelly) is no longer finite: x ("), std::string::npos)
      << err_;
  EXPECT_NE(err_.find("v (nan, "), std::string::npos) << err_;
  EXPECT_NE(err_.find("lower time.cfl or time.max_dt"), std::string::npos) << err_;
  // The frames before the step and their checkpoint stay, and none after it was written.
  const int done = int(stats(run).size()) - 1;
  EXPECT_GE(done, 1);
  EXPECT_NE(err_.find("the last good checkpoint (frame " + std::to_string(done)),
            std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(run + "/frames/0000" + std::to_string(done + 1) + ".ply"));
  // Without the NaN the same run completes.
  EXPECT_EQ(tear("run " + s + " -o " + run + " -q"), 0) << err_;
}

TEST_F(LongRun, MaxMemoryRefusesARunWhoseEstimateIsLarger) {
  const std::string s = write_scene(scene());
  EXPECT_EQ(tear("run " + s + " -o " + path("run") + " -q --max-memory 10k"), 1) << err_;
  EXPECT_NE(err_.find("(tear check), more than --max-memory 10.0 KiB"), std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(path("run")));
  EXPECT_EQ(tear("run " + s + " -o " + path("run") + " -q --max-memory 1G"), 0) << err_;
  EXPECT_EQ(tear("run " + s + " -o " + path("run2") + " -q --max-memory 0"), 0) << err_;
  EXPECT_EQ(tear("run " + s + " -o " + path("run3") + " -q --max-memory 12X"), 2) << err_;
  EXPECT_NE(err_.find("unknown unit 'X'"), std::string::npos) << err_;
}

// N frames against N/2 and a resume, for the kinds of state a checkpoint must carry: explicit
// damage, implicit damage (the damage solve), plasticity (the plastic state).
TEST_F(LongRun, ResumeIsBitIdenticalForDamageAndPlasticScenes) {
  struct Case {
    const char* name;
    std::vector<std::string> sets;
  };
  const Case cases[] = {
      {"explicit_damage",
       {"materials.jelly.damage={\"sigma_c\":20,\"eta\":0.2}", "damage.solver=explicit"}},
      {"implicit_damage",
       {"materials.jelly.damage={\"sigma_c\":20,\"eta\":0.2}", "damage.solver=implicit"}},
      {"plastic",
       {"materials.jelly.plasticity={\"type\":\"von_mises\",\"yield_stress\":40}"}},
  };
  for (const Case& c : cases) {
    json j = scene();
    j["time"]["frames"] = 8;
    j["output"]["checkpoint_every"] = 4;
    const std::string s = write_scene(j, std::string(c.name) + ".json");
    std::string sets;
    for (const std::string& k : c.sets) sets += " --set '" + k + "'";
    const std::string full = path(std::string(c.name) + "_full"),
                      part = path(std::string(c.name) + "_part");
    ASSERT_EQ(tear("run " + s + " -o " + full + " -q" + sets), 0) << c.name << err_;
    ASSERT_EQ(tear("run " + s + " -o " + part + " -q --frames 4" + sets), 0) << c.name << err_;
    ASSERT_EQ(tear("run " + s + " -o " + part + " -q --resume" + sets), 0) << c.name << err_;
    expect_same_run(full, part, 8);
    // The comparison means something: the state changed in the way the case is about.
    if (std::string(c.name) != "plastic") {
      EXPECT_GT(stats(full).back()["max_damage"].get<double>(), 0.1) << c.name;
    } else {
      ASSERT_EQ(tear("run " + s + " -o " + path("elastic") + " -q"), 0) << err_;
      EXPECT_NE(read_file(full + "/frames/00008.ply"), read_file(path("elastic/frames/00008.ply")));
    }
  }
}

// The step guard end to end (docs/long-runs.md "Steps that would move too far"): the grip jerks
// the disk's top up at 100 for a millisecond, 100 dt / dx = 1.3 cells at the wave speed's dt
// (over twice cfl = 0.8): the first steps are redone shorter, stats.jsonl counts them, frames
// still land on their times, and a resume after them is bit-identical.
TEST_F(LongRun, StepsThatWouldMoveTooFarAreRedoneCountedAndResumable) {
  json j = scene();
  j["boundaries"][1]["velocity"] = json::array({0, 100});
  j["boundaries"][1]["end"] = 0.001;
  j["time"]["frames"] = 4;
  j["output"]["checkpoint_every"] = 1;
  const std::string s = write_scene(j);
  const std::string full = path("full"), part = path("part");
  ASSERT_EQ(tear("run " + s + " -o " + full + " -q"), 0) << err_;
  const std::vector<json> lines = stats(full);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0]["steps_redone"], 0);
  EXPECT_GE(lines[1]["steps_redone"].get<int>(), 1);
  for (size_t f = 0; f < lines.size(); ++f)
    EXPECT_EQ(lines[f]["time"].get<double>(), 0.02 * double(f)) << "frame " << f;
  // Without the jerk nothing is redone.
  ASSERT_EQ(tear("run " + write_scene(scene(), "calm.json") + " -o " + path("calm") + " -q"), 0)
      << err_;
  for (const json& l : stats(path("calm"))) EXPECT_EQ(l["steps_redone"], 0);
  // Two frames, then the rest from the checkpoint: the same frames and stats.
  ASSERT_EQ(tear("run " + s + " -o " + part + " -q --frames 2"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + part + " -q --resume"), 0) << err_;
  expect_same_run(full, part, 4);
}

}  // namespace
}  // namespace tear
