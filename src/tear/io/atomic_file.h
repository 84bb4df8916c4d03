// io/: files on disk. Every file is written to a temporary beside its target, then renamed,
// so a reader never sees half a file.
#pragma once

#include "tear/io/binary.h"

#include <string>
#include <vector>

namespace tear {

// How write_file_atomic put the bytes into the file.
enum class WriteWay {
  stream,  // write()
  mapped,  // blocks reserved (fallocate), then copied into a shared mapping in parallel
};

// Files of at least this many bytes are written mapped where parallel loops have more than one
// thread (exec/threads.h allowed_threads) and the file system reserves blocks on fallocate
// (ext2/3/4, XFS, Btrfs, tmpfs, overlayfs on Linux), so that no store into the mapping can meet
// a full disk; smaller files, and files elsewhere or on one thread, as a stream.
constexpr size_t kMappedWriteBytes = size_t(4) << 20;

// Write `bytes` to `path` atomically (temp file ".NAME.tmp.PID" in the same folder + rename).
// Throws std::runtime_error naming the path and the system's reason on failure, and leaves no
// temporary behind. For tests of what a run does when the disk fails: where the environment
// variable TEAR_TEST_FAIL_WRITE is "TEXT" or "TEXT,EACCES", a write to a path containing TEXT
// fails as the disk being full (streamed: half the bytes written, then ENOSPC; mapped: at the
// reservation) or permission denied (at the open).
WriteWay write_file_atomic(const std::string& path, const std::string& bytes);
// The same for bytes in pieces, each written from where it is.
WriteWay write_file_atomic(const std::string& path, const ByteWriter& bytes);

// Whether files of kMappedWriteBytes or more written into `folder` with more than one thread are
// written mapped (its file system is one of those above).
bool writes_mapped_in(const std::string& folder);

// Removes the temporaries write_file_atomic leaves when the process is killed mid-write
// (".NAME.tmp.PID" files) from folder `dir`; returns how many. A missing folder has none.
int remove_stale_temporaries(const std::string& dir);

// Each line followed by '\n', written atomically (stats.jsonl is rewritten every frame).
void write_lines_atomic(const std::string& path, const std::vector<std::string>& lines);

// The whole file; throws std::runtime_error naming the path if it cannot be read or is a
// device (which would never end).
std::string read_file(const std::string& path);

// mkdir -p; throws std::runtime_error naming the path on failure.
void make_directories(const std::string& path);

}  // namespace tear
