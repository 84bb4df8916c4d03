// driver/: what the `tear` commands share: the one-line error, the thread cap, the frames of a
// run folder within a --frames range, and clock-style durations for progress lines.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tear/exec/threads.h"
#include "tear/io/frames.h"

namespace tear {

// What `tear` exits with (docs/long-runs.md "Exit codes").
enum ExitCode : int {
  kExitOk = 0,
  kExitError = 1,     // bad input, a failed write, a refused resume: one line on stderr
  kExitUsage = 2,     // command-line usage (CLI11)
  kExitUnstable = 3,  // the simulation blew up: a particle non-finite or out of the domain
  kExitInterrupted = 130,  // stopped by SIGINT after writing a checkpoint (128 + 2)
  kExitTerminated = 143,   // stopped by SIGTERM after writing a checkpoint (128 + 15)
};

// Prints "tear: reason" on stderr (line breaks become spaces) and returns `code`.
int fail(std::string why, int code = 1);

// Caps every parallel loop at `threads` threads while the result lives; 0: no cap (all cores).
std::unique_ptr<ThreadLimit> limit_threads(int threads);

// The frames of run folder `dir` within `range`, by frame number. Throws std::runtime_error
// "DIR: no such folder", "DIR: no frames/ folder", or "DIR: no frames [in --frames A:B]".
std::vector<FrameFile> frames_in_range(const std::string& dir, const FrameRange& range);

// "m:ss", or "h:mm:ss" from an hour on; "--:--" when unknown (negative or not finite).
std::string clock_text(double seconds);

}  // namespace tear
