// render/: a preview video from rendered frames, through the ffmpeg executable.
#pragma once

#include <string>
#include <vector>

namespace tear {

// Encodes the PNG files `frames` (in this order, one video frame each) as H.264 (yuv420p; odd
// sizes padded by a pixel) in an MP4 at `fps` frames per second, with the `ffmpeg` found on
// PATH. The video is written beside `out` under a temporary name and renamed into place.
// Returns false, writing nothing, when there is no ffmpeg on PATH; throws std::runtime_error
// naming `out` and ffmpeg's last message when ffmpeg fails. `threads` > 0 limits ffmpeg's.
// The ffmpeg executable make_video would start (the first on PATH); empty when there is none.
std::string ffmpeg_path();

bool make_video(const std::vector<std::string>& frames, double fps, const std::string& out,
                int threads = 0);

}  // namespace tear
