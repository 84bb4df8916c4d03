// Replays a fuzz target's corpus in the normal test suite (ctest Fuzz.replay_NAME): runs
// LLVMFuzzerTestOneInput once on every file of the folders or files given, in name order, and
// on the seeds the target makes itself (TearFuzzSeeds). A crash or abort ends the process; an
// exception that escapes the target (not a std::exception it rejected) fails with the input's
// name. `--write-seeds DIR` writes the target's own seeds into DIR instead.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

namespace fs = std::filesystem;

int failures = 0;
size_t inputs = 0;

void replay(const std::string& name, const std::string& bytes) {
  ++inputs;
  try {
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: the target let a std::exception escape: %s\n", name.c_str(),
                 e.what());
    ++failures;
  } catch (...) {
    std::fprintf(stderr, "%s: the target let a non-std exception escape\n", name.c_str());
    ++failures;
  }
}

std::string seed_dir;

void replay_seed(const char* name, const uint8_t* data, size_t size) {
  replay(std::string("(seed) ") + name, std::string(reinterpret_cast<const char*>(data), size));
}

void write_seed(const char* name, const uint8_t* data, size_t size) {
  const fs::path path = fs::path(seed_dir) / name;
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", path.string().c_str());
    ++failures;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 2 && args[0] == "--write-seeds") {
    if (!TearFuzzSeeds) {
      std::fprintf(stderr, "this target makes no seeds of its own\n");
      return 2;
    }
    seed_dir = args[1];
    fs::create_directories(seed_dir);
    TearFuzzSeeds(write_seed);
    return failures ? 1 : 0;
  }
  if (args.empty()) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR_OR_FILE... | --write-seeds DIR\n", argv[0]);
    return 2;
  }
  std::vector<fs::path> files;
  for (const std::string& a : args) {
    if (fs::is_directory(a)) {
      for (const fs::directory_entry& e : fs::recursive_directory_iterator(a))
        if (e.is_regular_file()) files.push_back(e.path());
    } else if (fs::is_regular_file(a)) {
      files.push_back(a);
    } else {
      std::fprintf(stderr, "%s: no such file or folder\n", a.c_str());
      return 2;
    }
  }
  std::sort(files.begin(), files.end());
  if (TearFuzzSeeds) TearFuzzSeeds(replay_seed);
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) {
      std::fprintf(stderr, "%s: cannot read\n", f.string().c_str());
      return 2;
    }
    replay(f.string(), bytes);
  }
  if (inputs == 0) {
    std::fprintf(stderr, "no inputs to replay\n");
    return 2;
  }
  std::printf("%zu inputs replayed, %d failed\n", inputs, failures);
  return failures ? 1 : 0;
}
