// driver/: `tear cracks`: the crack figures of a run's frames in rest space (cracked share,
// crack direction, band width; damage/crack_metrics.h), one line per frame or JSON
// (docs/cli.md).
#pragma once

#include <string>

namespace tear {

struct CrackReportOptions {
  std::string dir;        // a run folder (DIR/frames/)
  std::string frames;     // "A:B", "A:", ":B", "A" or "" (all)
  double threshold = 0.5;  // cracked: damage above this
  double spacing = 0;     // particle spacing; 0: from DIR/scene.json, else estimated
  bool json = false;      // one JSON object per frame instead of a table
};

// `tear cracks`. Returns the exit code (1: bad input, 2: a malformed --frames).
int crack_report(const CrackReportOptions& options);

}  // namespace tear
