// docs/gallery.md keeps up with examples/: every example has a still (a PNG that decodes, of
// the size scripts/make_gallery.sh renders) and a section on the page; every paper demo
// (examples/paper/) has two, in world and in rest space; every cloth, yarn and hair scene
// (examples/codimensional/) and FEM scene (examples/fem/) one.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tear/io/atomic_file.h"
#include "tear/render/image.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

void expect_still(const fs::path& png, const std::string& name) {
  ASSERT_TRUE(fs::exists(png)) << "run: bash scripts/make_gallery.sh " << name;
  const Image image = decode_png(read_file(png.string()));
  EXPECT_EQ(image.width, 480);
  EXPECT_EQ(image.height, 270);
  EXPECT_LT(fs::file_size(png), 150u * 1024) << "keep the stills small";
}

TEST(Gallery, EveryExampleHasAStillAndASection) {
  const fs::path root(TEAR_SOURCE_DIR);
  // NAME for examples/NAME.json, paper/NAME for examples/paper/NAME.json, likewise
  // codimensional/NAME and fem/NAME.
  std::vector<std::string> names, stills;
  for (const char* folder : {"", "paper", "codimensional", "fem"})
    for (const auto& e : fs::directory_iterator(root / "examples" / folder))
      if (e.path().extension() == ".json") {
        const std::string name = (fs::path(folder) / e.path().stem()).generic_string();
        names.push_back(name);
        stills.push_back(name);
        if (std::string(folder) == "paper") stills.push_back(name + "_rest");
      }
  std::sort(names.begin(), names.end());
  std::sort(stills.begin(), stills.end());
  ASSERT_FALSE(names.empty());
  const std::string page = read_file((root / "docs" / "gallery.md").string());
  for (const std::string& n : names) {
    SCOPED_TRACE(n);
    EXPECT_NE(page.find("## " + fs::path(n).filename().string() + "\n"), std::string::npos);
  }
  for (const std::string& n : stills) {
    SCOPED_TRACE(n);
    EXPECT_NE(page.find("(gallery/" + n + ".png)"), std::string::npos);
    expect_still(root / "docs" / "gallery" / (n + ".png"), n);
  }
  // No still without its example.
  for (const auto& e : fs::recursive_directory_iterator(root / "docs" / "gallery")) {
    if (e.is_directory()) continue;
    const std::string still =
        fs::relative(e.path(), root / "docs" / "gallery").replace_extension().generic_string();
    EXPECT_TRUE(std::binary_search(stills.begin(), stills.end(), still))
        << e.path() << " has no example";
  }
}

}  // namespace
}  // namespace tear
