// io/: files on disk. Every file is written to a temporary beside its target, then renamed,
// so a reader never sees half a file.
#pragma once

#include <string>
#include <vector>

namespace tear {

// Write `bytes` to `path` atomically (temp file in the same folder + rename). Throws
// std::runtime_error naming the path and the system's reason on failure.
void write_file_atomic(const std::string& path, const std::string& bytes);

// Each line followed by '\n', written atomically (stats.jsonl is rewritten every frame).
void write_lines_atomic(const std::string& path, const std::vector<std::string>& lines);

// The whole file; throws std::runtime_error naming the path if it cannot be read.
std::string read_file(const std::string& path);

// mkdir -p; throws std::runtime_error naming the path on failure.
void make_directories(const std::string& path);

}  // namespace tear
