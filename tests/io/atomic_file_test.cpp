#include "tear/io/atomic_file.h"

#include "tear/exec/threads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>

namespace tear {
namespace {

namespace fs = std::filesystem;

// A fresh folder under the system temp folder, removed with everything in it.
class ScratchDir {
 public:
  ScratchDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("tear_atomic_file_test_" + std::to_string(rd()) + "_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  // Names of the entries directly inside the folder.
  std::set<std::string> entries() const {
    std::set<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(path_))
      names.insert(e.path().filename().string());
    return names;
  }

 private:
  fs::path path_;
};

// The message of the runtime_error that `f` throws, or "no error".
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(AtomicFile, WritesArbitraryBytesExactly) {
  ScratchDir dir;
  std::string bytes(3 << 20, '\0');  // larger than any stdio buffer, with NULs and 0xFF
  std::mt19937 rng(7);
  for (char& c : bytes) c = char(rng() & 0xFF);
  write_file_atomic(dir.file("frame.ply"), bytes);
  EXPECT_EQ(fs::file_size(dir.file("frame.ply")), bytes.size());
  EXPECT_TRUE(read_file(dir.file("frame.ply")) == bytes);
  write_file_atomic(dir.file("empty"), "");
  EXPECT_EQ(read_file(dir.file("empty")), "");
  EXPECT_EQ(dir.entries(), (std::set<std::string>{"empty", "frame.ply"}));
}

// Pieces of every kind (copied and referenced, empty, one byte, across the 1 MiB copies of a
// mapped write, ending off any boundary) make the same file mapped and streamed.
ByteWriter pieces_of(const std::string& bytes, std::deque<std::string>* keep) {
  ByteWriter w;
  size_t at = 0;
  const size_t sizes[] = {1, 0, 7, (1 << 20) + 3, 4096, 12345, (2 << 20) - 1, 1};
  for (size_t k = 0; at < bytes.size(); ++k) {
    const size_t n = std::min(sizes[k % 8], bytes.size() - at);
    if (k % 2 == 0) {
      w.put_bytes(bytes.data() + at, n);
    } else {
      keep->push_back(bytes.substr(at, n));
      w.put_view(keep->back().data(), n);
    }
    at += n;
  }
  return w;
}

TEST(AtomicFile, LargeFilesAreMappedWithTheSameBytes) {
  ScratchDir dir;
  if (!writes_mapped_in(dir.file("")))
    GTEST_SKIP() << "the temp folder's file system is not one that tear writes mapped";
  std::mt19937 rng(11);
  for (const int threads : {2, 1})
    for (const size_t size :
         {kMappedWriteBytes - 1, kMappedWriteBytes, 3 * kMappedWriteBytes + 5}) {
      const ThreadLimit limit(threads);
      std::string bytes(size, '\0');
      for (char& c : bytes) c = char(rng() & 0xFF);
      std::deque<std::string> keep;  // the views' bytes, which stay where they are
      const ByteWriter w = pieces_of(bytes, &keep);
      ASSERT_EQ(w.size(), size);
      const std::string path = dir.file("latest.bin");
      std::ofstream(path) << std::string(size + 100, 'x');  // an older, longer file is replaced
      const WriteWay way = write_file_atomic(path, w);
      const bool mapped = size >= kMappedWriteBytes && allowed_threads() > 1;
      EXPECT_EQ(way, mapped ? WriteWay::mapped : WriteWay::stream) << size << " " << threads;
      EXPECT_EQ(fs::file_size(path), size);
      EXPECT_TRUE(read_file(path) == bytes) << size;
      EXPECT_EQ(dir.entries(), std::set<std::string>{"latest.bin"});
    }
}

// A full disk shows at the reservation of a mapped file: the old file stays, no temporary.
TEST(AtomicFile, MappedWriteOnAFullDiskKeepsTheOldFile) {
  ScratchDir dir;
  if (!writes_mapped_in(dir.file("")))
    GTEST_SKIP() << "the temp folder's file system is not one that tear writes mapped";
  const std::string path = dir.file("00003.ply");
  write_file_atomic(path, "old");
  const ThreadLimit limit(2);
  if (allowed_threads() < 2) GTEST_SKIP() << "one core: files are not written mapped";
  ASSERT_EQ(::setenv("TEAR_TEST_FAIL_WRITE", "00003.ply", 1), 0);
  const std::string message =
      error_of([&] { write_file_atomic(path, std::string(kMappedWriteBytes, 'y')); });
  ::unsetenv("TEAR_TEST_FAIL_WRITE");
  EXPECT_TRUE(contains(message, path + ": cannot write: " + std::strerror(ENOSPC))) << message;
  EXPECT_EQ(read_file(path), "old");
  EXPECT_EQ(dir.entries(), std::set<std::string>{"00003.ply"});
}

TEST(AtomicFile, ReplacesLongerContentAndLeavesOnlyTheTarget) {
  ScratchDir dir;
  const std::string path = dir.file("stats.jsonl");
  std::ofstream(path) << "an older and much longer content than what replaces it\n";
  write_file_atomic(path, "new\n");
  EXPECT_EQ(read_file(path), "new\n");
  EXPECT_EQ(dir.entries(), std::set<std::string>{"stats.jsonl"});
}

TEST(AtomicFile, MissingFolderFailsNamingPathAndReason) {
  ScratchDir dir;
  const std::string path = dir.file("no/such/folder/00001.ply");
  const std::string message = error_of([&] { write_file_atomic(path, "x"); });
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, std::strerror(ENOENT))) << message;
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, FailedRenameKeepsTargetAndRemovesTemporary) {
  ScratchDir dir;
  const std::string path = dir.file("frames");
  fs::create_directories(path);  // a folder where the file should go: rename() refuses
  const std::string message = error_of([&] { write_file_atomic(path, "data"); });
  EXPECT_TRUE(contains(message, path + ": cannot replace: ")) << message;
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_EQ(dir.entries(), std::set<std::string>{"frames"});  // no .frames.tmp.<pid>
}

TEST(AtomicFile, PathWithoutFileNameIsRefused) {
  ScratchDir dir;
  const std::string path = dir.file("sub") + "/";
  EXPECT_TRUE(contains(error_of([&] { write_file_atomic(path, "x"); }), "not a file name"));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, WriteLinesEndsEveryLineAndShrinks) {
  ScratchDir dir;
  const std::string path = dir.file("stats.jsonl");
  write_lines_atomic(path, {"{\"frame\":0}", "", "{\"frame\":1}"});
  EXPECT_EQ(read_file(path), "{\"frame\":0}\n\n{\"frame\":1}\n");
  write_lines_atomic(path, {"{\"frame\":0}"});
  EXPECT_EQ(read_file(path), "{\"frame\":0}\n");
  write_lines_atomic(path, {});
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(read_file(path), "");
  EXPECT_EQ(dir.entries(), std::set<std::string>{"stats.jsonl"});
}

TEST(AtomicFile, ReadFileErrorsNamePathAndReason) {
  ScratchDir dir;
  const std::string missing = dir.file("absent.bin");
  const std::string message = error_of([&] { read_file(missing); });
  EXPECT_TRUE(contains(message, missing + ": cannot open: ")) << message;
  EXPECT_TRUE(contains(message, std::strerror(ENOENT))) << message;
  fs::create_directories(dir.file("folder"));
  const std::string folder = error_of([&] { read_file(dir.file("folder")); });
  EXPECT_TRUE(contains(folder, dir.file("folder") + ": cannot")) << folder;
}

// A scene may name any path; a device would be read forever (found by the scene fuzzer's
// review): refused at once.
TEST(AtomicFile, ReadFileRefusesDevices) {
  const std::string message = error_of([&] { read_file("/dev/zero"); });
  EXPECT_TRUE(contains(message, "/dev/zero: cannot read: a device, not a file")) << message;
}

// A run killed mid-write leaves ".NAME.tmp.PID"; only those are removed.
TEST(AtomicFile, RemoveStaleTemporariesRemovesOnlyOurs) {
  ScratchDir dir;
  for (const char* name : {".00003.ply.tmp.4242", ".stats.jsonl.tmp.7", "00003.ply", ".hidden",
                           ".x.tmp.", ".y.tmp.12a", "z.tmp.5"})
    write_file_atomic(dir.file(name), "x");
  EXPECT_EQ(remove_stale_temporaries(dir.file("")), 2);
  EXPECT_EQ(dir.entries(),
            (std::set<std::string>{"00003.ply", ".hidden", ".x.tmp.", ".y.tmp.12a", "z.tmp.5"}));
  EXPECT_EQ(remove_stale_temporaries(dir.file("absent")), 0);
}

TEST(AtomicFile, MakeDirectoriesIsMkdirP) {
  ScratchDir dir;
  make_directories(dir.file("out/frames"));
  EXPECT_TRUE(fs::is_directory(dir.file("out/frames")));
  make_directories(dir.file("out/frames"));  // already there: fine
  write_file_atomic(dir.file("plain"), "x");
  const std::string blocked = dir.file("plain/checkpoints");
  const std::string message = error_of([&] { make_directories(blocked); });
  EXPECT_TRUE(contains(message, blocked + ": cannot create folder: ")) << message;
}

}  // namespace
}  // namespace tear
