#include "tear/surface/level_set.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace tear {

namespace {

// $TEAR_MODULE_DIR alone where it is set, else the program's folder, then the build folder.
std::vector<std::string> module_folders() {
  std::vector<std::string> out;
  if (const char* dir = std::getenv("TEAR_MODULE_DIR"); dir && *dir) return {dir};
  std::error_code error;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) out.push_back(program.parent_path().string());
#ifdef TEAR_MODULE_DIR
  out.push_back(TEAR_MODULE_DIR);
#endif
  return out;
}

const LevelSetModule* load_module() {
  std::string tried;
  for (const std::string& folder : module_folders()) {
    const std::string path = folder + "/" TEAR_LEVEL_SET_FILE;
    std::string why;
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
      why = "no such file";
    } else if (void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
      using Entry = const LevelSetModule* (*)();
      const auto entry = reinterpret_cast<Entry>(dlsym(handle, TEAR_LEVEL_SET_ENTRY));
      const LevelSetModule* module = entry ? entry() : nullptr;
      if (module && module->abi == kLevelSetAbi) return module;  // kept loaded
      why = !module ? "no entry point " TEAR_LEVEL_SET_ENTRY
                    : "built by another version of tear (interface " +
                          std::to_string(module->abi) + ", this one " +
                          std::to_string(kLevelSetAbi) + ")";
      dlclose(handle);
    } else {
      why = dlerror();
    }
    tried += (tried.empty() ? "" : "; ") + path + ": " + why;
  }
  throw std::runtime_error(
      "the surface mesher needs its OpenVDB module " TEAR_LEVEL_SET_FILE
      ", which could not be loaded (" +
      tried + "); build the target tear_level_set and keep it beside tear, or set "
              "TEAR_MODULE_DIR to the folder that holds it");
}

}  // namespace

const LevelSetModule& level_set_module() {
  static std::mutex mutex;
  static const LevelSetModule* module = nullptr;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!module) module = load_module();
  return *module;
}

}  // namespace tear
