// Fuzz target: the scene loader (load_scene_text) with `tear run --set` overrides. The input is
// the scene's JSON text, then each override after a NUL byte ("JSON\0a.b=1\0c=x"); an override
// "@resolution=K" is `--resolution K` instead. A loaded scene's resolved JSON (every default
// filled in) must load again.
#include <cstdlib>
#include <vector>

#include "fuzz_util.h"
#include "tear/scene/scene.h"

using namespace tear;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input = fuzz::bytes_of(data, size);
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t nul = input.find('\0', start);
    parts.push_back(input.substr(start, nul == std::string::npos ? nul : nul - start));
    if (nul == std::string::npos) break;
    start = nul + 1;
  }
  double resolution = 1;
  std::vector<std::string> overrides;
  for (size_t i = 1; i < parts.size(); ++i) {
    if (parts[i].rfind("@resolution=", 0) == 0)
      resolution = std::strtod(parts[i].c_str() + 12, nullptr);
    else
      overrides.push_back(parts[i]);
  }
  // A folder that does not exist: mesh and particle files named relatively are not found.
  const std::string path = "/nonexistent-tear-fuzz/scene.json";
  Scene s;
  if (!fuzz::accepts([&] { s = load_scene_text(parts[0], path, overrides, resolution); }))
    return 0;
  try {
    parse_scene(s.resolved, path);
  } catch (const std::exception& e) {
    fuzz::finding(std::string("the resolved scene does not load: ") + e.what());
  }
  return 0;
}
