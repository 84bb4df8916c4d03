#include "tear/exec/plugin.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <map>
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

const PluginHeader* open_plugin(const char* file, const char* entry, int abi, const char* purpose,
                                const char* target) {
  std::string tried;
  for (const std::string& folder : module_folders()) {
    const std::string path = folder + "/" + file;
    std::string why;
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
      why = "no such file";
    } else if (void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
      using Entry = const PluginHeader* (*)();
      const auto fn = reinterpret_cast<Entry>(dlsym(handle, entry));
      const PluginHeader* module = fn ? fn() : nullptr;
      if (module && module->abi == abi) return module;  // kept loaded
      why = !module ? std::string("no entry point ") + entry
                    : "built by another version of tear (interface " +
                          std::to_string(module->abi) + ", this one " + std::to_string(abi) + ")";
      dlclose(handle);
    } else {
      why = dlerror();
    }
    tried += (tried.empty() ? "" : "; ") + path + ": " + why;
  }
  throw std::runtime_error(std::string(purpose) + " " + file + ", which could not be loaded (" +
                           tried + "); build the target " + target +
                           " and keep it beside tear, or set TEAR_MODULE_DIR to the folder that "
                           "holds it");
}

}  // namespace

const PluginHeader* load_plugin(const char* file, const char* entry, int abi, const char* purpose,
                                const char* target) {
  static std::mutex mutex;
  static std::map<std::string, const PluginHeader*> loaded;
  const std::lock_guard<std::mutex> lock(mutex);
  const PluginHeader*& module = loaded[file];
  if (!module) module = open_plugin(file, entry, abi, purpose, target);
  return module;
}

}  // namespace tear
