// driver/: what the `tear` subcommands do (run, check, info), as library functions so that
// nothing important lives only in the CLI. Owns the output folder layout (ARCHITECTURE.md
// "Outputs"), progress display and resuming.
#pragma once

#include "tear/driver/render_frames.h"

#include <ostream>
#include <string>
#include <vector>

namespace tear {

struct RunOptions {
  std::string scene_path;
  std::string out_dir;
  int threads = 0;                     // 0: all hardware threads
  int frames = -1;                     // >= 0 overrides time.frames
  std::vector<std::string> overrides;  // --set KEY=VALUE
  double resolution = 1;               // --resolution K: grid.dx and time.max_dt divided by K
  bool quiet = false;                  // no progress line
  bool resume = false;                 // continue DIR's run from its checkpoint
  bool render = false;                 // --render: DIR/render/NNNNN.png per frame, preview.mp4
  RenderOverrides render_options;      // with --render
  // --max-memory in bytes: refuse a run whose memory estimate (tear check's) is larger; 0: no
  // limit; < 0: 90 % of the machine's physical memory.
  double max_memory = -1;
};

// `tear run`. Returns the exit code (ExitCode, driver/command.h); errors are one line
// "tear: reason" on stderr. An invalid scene writes nothing; a fresh run replaces the outputs
// of an earlier run in the folder. SIGINT and SIGTERM stop it after the step in progress with a
// checkpoint (docs/long-runs.md).
int run_scene(const RunOptions& options);

// `tear check`: validate the scene and print what a run would do. Returns the exit code.
int check_scene(const std::string& scene_path, const std::vector<std::string>& overrides,
                double resolution, std::ostream& out);

// `tear info`: version, build options, libraries and threads.
void print_info(std::ostream& out);

}  // namespace tear
