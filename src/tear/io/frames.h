// io/: the frames of a run folder (DIR/frames/NNNNN.EXT) as files and as point
// tables, whatever format they were written in; what `tear convert`, `tear
// mesh` and `tear render` read.
#pragma once

#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

// The point formats a run can write (scene "output.formats"), in order of
// preference for reading: when a frame exists in several formats, readers take
// the first of these.
const std::vector<std::string> &point_formats();
// point_formats() joined by `separator`, for messages: "ply, bgeo, vtu".
std::string point_format_list(const std::string &separator = ", ");
// Whether `format` is one of point_formats().
bool is_point_format(const std::string &format);

// DIR/frames/NNNNN.EXT (five digits at least, as the run writes them).
std::string frame_path(const std::string &dir, int frame, const std::string &format);

struct FrameFile {
  int frame = 0;
  std::string path;    // DIR/frames/NNNNN.EXT
  std::string format;  // one of point_formats()
};

// Frames in DIR/frames, one per frame number (preferring the earlier of
// point_formats()), sorted by frame. Throws std::runtime_error naming DIR when
// it has no frames folder.
std::vector<FrameFile> list_frames(const std::string &dir);
// The frames of DIR stored in `format`, sorted by frame (empty when there are none).
std::vector<FrameFile> list_frames(const std::string &dir, const std::string &format);

// An inclusive range of frame numbers; "A:B", "A:" (to the end), ":B", "A" (one
// frame) or
// "" (all).
struct FrameRange {
  int first = 0;
  int last = -1;  // -1: no upper limit
  bool contains(int frame) const { return frame >= first && (last < 0 || frame <= last); }
};
// Throws std::runtime_error quoting `text` and the expected form when it does
// not parse.
FrameRange parse_frame_range(const std::string &text);

// Decode a frame file by its extension; throws std::runtime_error naming `path`
// and the reason.
PointTable read_frame(const std::string &path);
// Encode a table in `format` (one of point_formats()).
std::string encode_points(const PointTable &table, const std::string &format);
// Encode rows in `format` into `out` (its storage reused). PLY is written a chunk of rows at a
// time; the other formats are column by column and take the whole table first (into
// `scratch` where given, whose storage is reused).
void encode_points(const PointRows &rows, const std::string &format, std::string *out,
                   PointTable *scratch = nullptr);

}  // namespace tear
