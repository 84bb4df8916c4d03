#include "tear/io/atomic_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

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

}  // namespace

// The temporary sits in the target's folder, so rename() stays on one file system and is
// atomic: a reader sees the old file or the new one, never a mix. No fsync: this guards
// against readers during the run, not against power loss.
void write_file_atomic(const std::string& path, const ByteWriter& bytes) {
  const fs::path target(path);
  if (target.filename().empty())
    throw std::runtime_error("'" + path + "': cannot write: not a file name");
  const fs::path temp = target.parent_path() / ("." + target.filename().string() + ".tmp." +
                                                std::to_string(::getpid()));
  const int injected = injected_failure(path);
  std::FILE* f = injected == EACCES ? nullptr : std::fopen(temp.c_str(), "wb");
  if (!f) throw os_error(path, "cannot write", injected ? injected : errno);
  int err = 0;
  errno = 0;
  // Half the bytes where a failure is injected, then the failure.
  size_t left = injected ? bytes.size() / 2 : bytes.size();
  bytes.for_each_piece([&](const char* data, size_t size) {
    const size_t k = std::min(size, left);
    if (err == 0 && k > 0 && std::fwrite(data, 1, k, f) != k) err = errno ? errno : EIO;
    left -= k;
  });
  if (injected) err = injected;
  if (err == 0 && std::fflush(f) != 0) err = errno ? errno : EIO;
  if (std::fclose(f) != 0 && err == 0) err = errno ? errno : EIO;
  if (err != 0) {
    std::remove(temp.c_str());
    throw os_error(path, "cannot write", err);
  }
  if (std::rename(temp.c_str(), target.c_str()) != 0) {
    err = errno;
    std::remove(temp.c_str());
    throw os_error(path, "cannot replace", err);
  }
}

void write_file_atomic(const std::string& path, const std::string& bytes) {
  ByteWriter w;
  w.put_view(bytes.data(), bytes.size());
  write_file_atomic(path, w);
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
    if (ours && e.is_regular_file(ec) && fs::remove(e.path(), ec))
      ++removed;
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
