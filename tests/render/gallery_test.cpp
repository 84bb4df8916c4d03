// docs/gallery.md keeps up with examples/: every example has a still (a PNG that decodes, of
// the size scripts/make_gallery.sh renders) and a section on the page.
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

TEST(Gallery, EveryExampleHasAStillAndASection) {
  const fs::path root(TEAR_SOURCE_DIR);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(root / "examples"))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  ASSERT_FALSE(names.empty());
  const std::string page = read_file((root / "docs" / "gallery.md").string());
  for (const std::string& n : names) {
    SCOPED_TRACE(n);
    EXPECT_NE(page.find("## " + n + "\n"), std::string::npos);
    EXPECT_NE(page.find("(gallery/" + n + ".png)"), std::string::npos);
    const fs::path png = root / "docs" / "gallery" / (n + ".png");
    ASSERT_TRUE(fs::exists(png)) << "run: bash scripts/make_gallery.sh " << n;
    const Image image = decode_png(read_file(png.string()));
    EXPECT_EQ(image.width, 480);
    EXPECT_EQ(image.height, 270);
    EXPECT_LT(fs::file_size(png), 150u * 1024) << "keep the stills small";
  }
  // No still without its example.
  for (const auto& e : fs::directory_iterator(root / "docs" / "gallery"))
    EXPECT_TRUE(std::binary_search(names.begin(), names.end(), e.path().stem().string()))
        << e.path() << " has no example";
}

}  // namespace
}  // namespace tear
