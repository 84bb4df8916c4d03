#include "tear/io/atomic_file.h"

#include "tear/exec/parallel.h"
#include "tear/exec/threads.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#if defined(__linux__)
#include <linux/magic.h>
#include <sys/mman.h>
#include <sys/vfs.h>
#endif

namespace tear {

namespace fs = std::filesystem;

namespace {

std::runtime_error os_error(const std::string& path, const char* what, int err) {
  return std::runtime_error(path + ": " + what + ": " + std::strerror(err));
}

// TEAR_TEST_FAIL_WRITE (see the header): 0, or the errno a write to `path` must fail with.
int injected_failure(const std::string& path) {
  const char* env = std::getenv("TEAR_TEST_FAIL_WRITE");
  if (!env || !*env) return 0;
  std::string text = env;
  int err = ENOSPC;
  const size_t comma = text.rfind(',');
  if (comma != std::string::npos) {
    if (text.compare(comma + 1, std::string::npos, "EACCES") == 0) err = EACCES;
    text.resize(comma);
  }
  return path.find(text) != std::string::npos ? err : 0;
}

// All of [data, data + size) to fd from where it is now, retrying short writes; 0 or errno.
int write_all(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t k = ::write(fd, data, size);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return k < 0 && errno ? errno : EIO;
    data += k, size -= size_t(k);
  }
  return 0;
}

#if defined(__linux__)
// File systems whose fallocate() reserves the blocks, so that a store into the mapped file
// cannot meet a full disk (which would be SIGBUS, not an error): elsewhere, write().
bool reserves_on_fallocate(int fd) {
  struct statfs fs {};
  if (::fstatfs(fd, &fs) != 0) return false;
  switch (static_cast<unsigned long>(fs.f_type)) {
    case EXT4_SUPER_MAGIC:  // also ext2 and ext3
    case XFS_SUPER_MAGIC:
    case BTRFS_SUPER_MAGIC:
    case TMPFS_MAGIC:
    case OVERLAYFS_SUPER_MAGIC:  // containers: the upper layer is one of the above
      return true;
    default: return false;
  }
}
#endif

// The bytes into the empty file fd through a shared mapping, 1 MiB pieces in parallel, after
// the file's blocks are reserved. Returns 0, the errno of a failure (a full disk shows at the
// reservation), or -1 where the file cannot be reserved or mapped (the caller writes instead).
int write_mapped(int fd, const ByteWriter& bytes, size_t size, int injected) {
#if defined(__linux__)
  if (!reserves_on_fallocate(fd)) return -1;
  if (injected) return injected;  // as a full disk would fail the reservation
  if (::fallocate(fd, 0, 0, off_t(size)) != 0)
    return errno == EOPNOTSUPP || errno == ENOSYS || errno == EINVAL ? -1 : errno;
  void* map = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (map == MAP_FAILED) return ::ftruncate(fd, 0) == 0 ? -1 : errno;
  struct Copy {
    char* to;
    const char* from;
    size_t size;
  };
  std::vector<Copy> copies;
  constexpr size_t kPiece = size_t(1) << 20;
  char* to = static_cast<char*>(map);
  bytes.for_each_piece([&](const char* data, size_t k) {
    for (size_t at = 0; at < k; at += kPiece)
      copies.push_back({to + at, data + at, std::min(kPiece, k - at)});
    to += k;
  });
  parallel_for(copies.size(),
               [&](size_t c) { std::memcpy(copies[c].to, copies[c].from, copies[c].size); });
  return ::munmap(map, size) == 0 ? 0 : errno;
#else
  (void)fd, (void)bytes, (void)size, (void)injected;
  return -1;
#endif
}

}  // namespace

// The temporary sits in the target's folder, so rename() stays on one file system and is
// atomic: a reader sees the old file or the new one, never a mix. No fsync: this guards
// against readers during the run, not against power loss.
//
// Large files (frames, checkpoints) go through a mapping where loops have several threads:
// write() fills the page cache on one core under the file's lock, while stores into a mapped
// file fault its pages in on every core at once. On the 2-core machine of docs/architecture.md
// a 95 MB checkpoint took 270-325 ms with write() and 110-125 ms mapped on 2 threads; 21 MB
// frames took the same either way. On one thread mapping is slower (faults cost more than
// write()'s copies: frames 1.3-1.5 times as long), so one thread streams.
WriteWay write_file_atomic(const std::string& path, const ByteWriter& bytes) {
  const fs::path target(path);
  if (target.filename().empty())
    throw std::runtime_error("'" + path + "': cannot write: not a file name");
  const fs::path temp = target.parent_path() /
                        ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()));
  const int injected = injected_failure(path);
  const int fd =
      injected == EACCES ? -1 : ::open(temp.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw os_error(path, "cannot write", injected ? injected : errno);
  const size_t size = bytes.size();
  int err = size >= kMappedWriteBytes && allowed_threads() > 1
                ? write_mapped(fd, bytes, size, injected)
                : -1;
  const WriteWay way = err < 0 ? WriteWay::stream : WriteWay::mapped;
  if (err < 0) {
    // Half the bytes where a failure is injected, then the failure.
    err = 0;
    size_t left = injected ? size / 2 : size;
    bytes.for_each_piece([&](const char* data, size_t k) {
      k = std::min(k, left);
      if (err == 0) err = write_all(fd, data, k);
      left -= k;
    });
    if (injected) err = injected;
  }
  if (::close(fd) != 0 && err == 0) err = errno ? errno : EIO;
  if (err != 0) {
    std::remove(temp.c_str());
    throw os_error(path, "cannot write", err);
  }
  if (std::rename(temp.c_str(), target.c_str()) != 0) {
    err = errno;
    std::remove(temp.c_str());
    throw os_error(path, "cannot replace", err);
  }
  return way;
}

bool writes_mapped_in(const std::string& folder) {
#if defined(__linux__)
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool mapped = reserves_on_fallocate(fd);
  ::close(fd);
  return mapped;
#else
  (void)folder;
  return false;
#endif
}

WriteWay write_file_atomic(const std::string& path, const std::string& bytes) {
  ByteWriter w;
  w.put_view(bytes.data(), bytes.size());
  return write_file_atomic(path, w);
}

int remove_stale_temporaries(const std::string& dir) {
  std::error_code ec;
  int removed = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const size_t tmp = name.rfind(".tmp.");
    const bool ours = name.size() > 1 && name[0] == '.' && tmp != std::string::npos &&
                      tmp + 5 < name.size() &&
                      name.find_first_not_of("0123456789", tmp + 5) == std::string::npos;
    if (ours && e.is_regular_file(ec) && fs::remove(e.path(), ec)) ++removed;
  }
  return removed;
}

void write_lines_atomic(const std::string& path, const std::vector<std::string>& lines) {
  size_t size = 0;
  for (const std::string& l : lines) size += l.size() + 1;
  std::string bytes;
  bytes.reserve(size);
  for (const std::string& l : lines) bytes.append(l).push_back('\n');
  write_file_atomic(path, bytes);
}

std::string read_file(const std::string& path) {
  // A device (/dev/zero, /dev/urandom) never ends: refused before reading.
  std::error_code type_ec;
  const fs::file_status st = fs::status(path, type_ec);
  if (!type_ec && (st.type() == fs::file_type::character || st.type() == fs::file_type::block))
    throw std::runtime_error(path + ": cannot read: a device, not a file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw os_error(path, "cannot open", errno);
  std::string bytes;
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  if (!ec) bytes.reserve(size_t(size));
  char buffer[1 << 16];
  size_t n;
  errno = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) bytes.append(buffer, n);
  // A folder opens but cannot be read (EISDIR).
  const int err = std::ferror(f) ? (errno ? errno : EIO) : 0;
  std::fclose(f);
  if (err != 0) throw os_error(path, "cannot read", err);
  return bytes;
}

void make_directories(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw std::runtime_error(path + ": cannot create folder: " + ec.message());
}

}  // namespace tear
