// driver/: `tear convert`: rewrites the frames of a run folder in another point format
// (docs/cli.md), and the frame times that DIR/frames.pvd lists.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "tear/io/frames.h"

namespace tear {

struct ConvertOptions {
  std::string dir;     // a run folder
  std::string format;  // one of point_formats()
  std::string frames;  // "A:B", "A:", ":B", "A" or "" (all)
};

struct ConvertCounts {
  size_t converted = 0;    // frames written in the format
  size_t skipped = 0;      // frames in the range that were already in the format
  size_t pvd_entries = 0;  // datasets in DIR/frames.pvd (VTU only)
  size_t meshes_converted = 0, meshes_skipped = 0;  // mesh parts (cloth, yarn, hair) likewise
};

// Writes DIR/frames/NNNNN.FORMAT, atomically, for every frame of DIR in `range` that is not yet
// in FORMAT (reading the frame in the first of point_formats() it exists in), then, for vtu,
// DIR/frames.pvd; for a mesh part format (mesh_part_formats()), likewise each frame's mesh
// parts DIR/frames/NNNNN.PART.FORMAT from their PLY files, and for vtu DIR/PART.pvd. A format of
// only one kind converts only that kind (obj: the meshes; bgeo: the particles). Throws std::runtime_error naming DIR and the reason (no such folder, no frames
// in the range, an unknown format with the known ones listed, a frame that cannot be read).
ConvertCounts convert_frames(const std::string& dir, const std::string& format,
                             const FrameRange& range);

// `tear convert`. Returns the exit code (1: bad input, 2: an unknown format or a malformed
// --frames); errors are one line "tear: reason" on stderr, the summary goes to stdout.
int convert_run(const ConvertOptions& options);

// The time of each frame in stats.jsonl lines (their "frame" and "time"); lines without both
// are skipped.
std::map<int, double> frame_times(const std::vector<std::string>& stats_lines);

}  // namespace tear
