// The module order of ARCHITECTURE.md "Layout", as declared by the tear_module() calls of the
// top-level CMakeLists.txt: every module uses only modules declared before it (in its DEPS and in
// its #includes), the core never sees the scene, and no code outside exec/ names TBB.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string source_dir() { return TEAR_SOURCE_DIR; }

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Module {
  std::string name;
  std::vector<std::string> deps;
};

// tear_module(NAME [DEPS tear_a tear_b ...]) calls, in file order.
std::vector<Module> declared_modules() {
  const std::string text = read(fs::path(source_dir()) / "CMakeLists.txt");
  std::vector<Module> out;
  const std::regex call(R"(\ntear_module\(([a-z_]+)([^)]*)\))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), call); it != std::sregex_iterator();
       ++it) {
    Module m{(*it)[1], {}};
    std::istringstream rest((*it)[2].str());
    std::string word;
    while (rest >> word)
      if (word.rfind("tear_", 0) == 0) m.deps.push_back(word.substr(5));
    out.push_back(m);
  }
  return out;
}

std::map<std::string, int> module_rank() {
  std::map<std::string, int> rank;
  for (const Module& m : declared_modules()) rank[m.name] = int(rank.size());
  rank["cli"] = int(rank.size());  // the executable, above every library
  return rank;
}

// (file, included module) for every #include "tear/<module>/..." in src/tear/<from>/ and its
// subfolders (surface/openvdb/: the mesher's module; fem/netgen/: the FEM mesher's).
std::vector<std::pair<std::string, std::string>> includes_of(const std::string& from) {
  std::vector<std::pair<std::string, std::string>> out;
  const std::regex inc(R"(#include\s+"tear/([a-z_]+)/)");
  const fs::path folder = fs::path(source_dir()) / "src/tear" / from;
  for (const auto& f : fs::recursive_directory_iterator(folder)) {
    if (!f.is_regular_file()) continue;
    const std::string text = read(f.path());
    for (auto it = std::sregex_iterator(text.begin(), text.end(), inc);
         it != std::sregex_iterator(); ++it)
      out.emplace_back(fs::relative(f.path(), folder).string(), (*it)[1]);
  }
  return out;
}

TEST(ModuleOrder, CMakeDeclaresTheArchitectureLayout) {
  std::vector<std::string> names;
  for (const Module& m : declared_modules()) names.push_back(m.name);
  const std::vector<std::string> layout = {
      "math",  "exec", "geometry", "kernels", "solvers", "materials", "particles", "grid", "damage",
      "codim", "mpm",  "fem",      "io",      "scene",   "surface",   "render",    "driver"};
  EXPECT_EQ(names, layout);
  // Every module folder is declared.
  for (const auto& d : fs::directory_iterator(fs::path(source_dir()) / "src/tear")) {
    const std::string name = d.path().filename().string();
    if (name == "cli") continue;
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end())
        << "src/tear/" << name << " is not a tear_module";
  }
}

TEST(ModuleOrder, DepsNameOnlyEarlierModules) {
  const std::map<std::string, int> rank = module_rank();
  for (const Module& m : declared_modules())
    for (const std::string& d : m.deps) {
      ASSERT_TRUE(rank.count(d)) << m.name << " depends on unknown module " << d;
      EXPECT_LT(rank.at(d), rank.at(m.name)) << m.name << " DEPS tear_" << d;
    }
}

TEST(ModuleOrder, IncludesGoOnlyToEarlierModules) {
  const std::map<std::string, int> rank = module_rank();
  for (const auto& [module, r] : rank)
    for (const auto& [file, used] : includes_of(module)) {
      ASSERT_TRUE(rank.count(used)) << module << "/" << file << " includes unknown module " << used;
      EXPECT_LE(rank.at(used), r) << "src/tear/" << module << "/" << file << " includes tear/"
                                  << used << "/ (declared later)";
    }
}

TEST(ModuleOrder, OnlyDriverAndCliSeeScenes) {
  for (const auto& [module, r] : module_rank()) {
    if (module == "driver" || module == "cli" || module == "scene") continue;
    for (const auto& [file, used] : includes_of(module))
      EXPECT_NE(used, "scene") << "src/tear/" << module << "/" << file << " includes scene/";
  }
}

TEST(ModuleOrder, NoThreadingLibraryOutsideExec) {
  const std::regex tbb(R"(tbb::|<tbb/|oneapi/tbb)");
  for (const auto& f : fs::recursive_directory_iterator(fs::path(source_dir()) / "src/tear")) {
    if (!f.is_regular_file() || f.path().parent_path().filename() == "exec") continue;
    EXPECT_FALSE(std::regex_search(read(f.path()), tbb))
        << f.path().string() << " names TBB; use exec/ (exec/parallel.h, exec/threads.h)";
  }
}

}  // namespace
