// io/: files on disk. Every file is written to a temporary beside its target, then renamed,
// so a reader never sees half a file.
#pragma once

#include <string>

namespace tear {

// Write `bytes` to `path` atomically (temp file in the same folder + rename). Throws
// std::runtime_error naming the path on failure.
void write_file_atomic(const std::string& path, const std::string& bytes);

std::string read_file(const std::string& path);

}  // namespace tear
