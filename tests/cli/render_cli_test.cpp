// End-to-end tests of `tear render` and `tear run --render`: pictures and video in the run
// folder, options over the scene's render section, determinism, resume, bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "cli_fixture.h"
#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"
#include "tear/render/camera.h"
#include "tear/render/image.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

bool have_ffmpeg() { return std::system("ffmpeg -version > /dev/null 2>&1") == 0; }

class RenderCli : public Cli {
 protected:
  // A finished small run (frames 0..4) in path("run").
  std::string run_folder(json scene_json = json()) {
    if (scene_json.is_null()) scene_json = scene();
    const std::string s = write_scene(scene_json);
    EXPECT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
    return path("run");
  }
  Image picture(const std::string& file) const { return decode_png(read_file(file)); }
};

constexpr const char* kSmall = " --width 96 --height 64 --samples 1";

TEST_F(RenderCli, RenderWritesAPicturePerFrameAndTheVideo) {
  const std::string run = run_folder();
  ASSERT_EQ(tear("render " + run + kSmall + " --threads 2"), 0) << err_;
  for (int f = 0; f <= 4; ++f) {
    const std::string png = run + "/render/0000" + std::to_string(f) + ".png";
    ASSERT_TRUE(fs::exists(png)) << png;
    const Image im = picture(png);
    EXPECT_EQ(im.width, 96);
    EXPECT_EQ(im.height, 64);
  }
  EXPECT_NE(out_.find("rendered 5 frames (96x64, damage)"), std::string::npos) << out_;
  EXPECT_NE(err_.find("render 5/5"), std::string::npos) << err_;  // progress on stderr
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not on PATH: no preview.mp4 expected";
  ASSERT_TRUE(fs::exists(run + "/preview.mp4"));
  EXPECT_EQ(read_file(run + "/preview.mp4").substr(4, 4), "ftyp");
  EXPECT_EQ(std::distance(fs::directory_iterator(run + "/render"), fs::directory_iterator{}), 5);
}

TEST_F(RenderCli, SameBytesForOneAndTwoThreadsAndFrameRanges) {
  const std::string run = run_folder();
  ASSERT_EQ(tear("render " + run + kSmall + " --threads 1 --no-video -q --frames 1:3"), 0) << err_;
  EXPECT_FALSE(fs::exists(run + "/render/00000.png"));
  EXPECT_FALSE(fs::exists(run + "/render/00004.png"));
  EXPECT_FALSE(fs::exists(run + "/preview.mp4"));
  EXPECT_EQ(err_, "");
  const std::string one = read_file(run + "/render/00003.png");
  ASSERT_EQ(tear("render " + run + kSmall + " --threads 2 --no-video -q --frames 1:3"), 0);
  EXPECT_EQ(read_file(run + "/render/00003.png"), one);
  // Another colour map gives another picture.
  ASSERT_EQ(tear("render " + run + kSmall + " --no-video -q --frames 3 --color velocity"), 0);
  EXPECT_NE(read_file(run + "/render/00003.png"), one);
}

TEST_F(RenderCli, SceneRenderSectionIsTheDefaultAndOptionsOverrideIt) {
  json s = scene();
  s["render"] = json::parse(R"({"width": 80, "height": 48, "samples": 1, "color": "fibers"})");
  const std::string run = run_folder(s);
  ASSERT_EQ(tear("render " + run + " --no-video --frames 0"), 0) << err_;
  EXPECT_EQ(picture(run + "/render/00000.png").width, 80);
  EXPECT_NE(out_.find("(80x48, fibers)"), std::string::npos) << out_;
  ASSERT_EQ(tear("render " + run + " --no-video --frames 0 --width 64 --color material"), 0);
  const Image im = picture(run + "/render/00000.png");
  EXPECT_EQ(im.width, 64);
  EXPECT_EQ(im.height, 48);
  EXPECT_NE(out_.find("(64x48, material)"), std::string::npos) << out_;
  // A given camera is used as is.
  ASSERT_EQ(tear("render " + run +
                 " --no-video --frames 0 --camera-position=0.5,0.5,3 --camera-target 0.5,0.5,0"
                 " --fov 20"),
            0)
      << err_;
  EXPECT_NE(err_.find("camera 0.5,0.5,3  target 0.5,0.5,0  fov 20"), std::string::npos) << err_;
}

// tear render frames the whole run: a body that flies off to the right is kept in the picture,
// the camera aims right of where it starts. Any frame range gets the same camera.
TEST_F(RenderCli, FittedCameraFramesEveryFrameOfTheRun) {
  json flying = scene();
  flying["gravity"] = {0, 0};
  flying["boundaries"] = json::array();
  flying["objects"][0]["velocity"] = {3, 0};
  flying["objects"][0]["angular_velocity"] = 0;
  flying["objects"][0]["shape"]["center"] = {0.3, 0.5};
  const std::string run = run_folder(flying);  // 4 frames of 0.02 s: the body moves 0.24
  const auto target_x = [&](const std::string& frames) {
    EXPECT_EQ(tear("render " + run + kSmall + " --no-video --frames " + frames), 0) << err_;
    const size_t at = err_.find("target ");
    EXPECT_NE(at, std::string::npos) << err_;
    return at == std::string::npos ? 0.0 : std::stod(err_.substr(at + 7));
  };
  const double all = target_x("0:4");
  EXPECT_NEAR(all, 0.3 + 0.12, 0.03);  // between the first and the last frame's centres
  EXPECT_EQ(target_x("0"), all);
  EXPECT_EQ(target_x("3:4"), all);
}

TEST_F(RenderCli, RunRenderRendersEveryWrittenFrameAndResumes) {
  json s = scene();
  s["output"]["every"] = 2;  // frames 0, 2, 4
  const std::string scene_path = write_scene(s);
  ASSERT_EQ(tear("run " + scene_path + " -o " + path("full") + " -q --render" + kSmall), 0) << err_;
  for (int f : {0, 2, 4})
    EXPECT_TRUE(fs::exists(path("full/render/0000" + std::to_string(f) + ".png")));
  EXPECT_FALSE(fs::exists(path("full/render/00001.png")));
  EXPECT_NE(out_.find("rendered 3 frames"), std::string::npos) << out_;
  if (have_ffmpeg()) {
    EXPECT_TRUE(fs::exists(path("full/preview.mp4")));
  }
  // The pictures of run --render are those of tear render.
  const std::string during = read_file(path("full/render/00004.png"));
  ASSERT_EQ(tear("render " + path("full") + kSmall + " --no-video -q"), 0) << err_;
  EXPECT_EQ(read_file(path("full/render/00004.png")), during);

  // Interrupted at frame 2 without pictures, resumed with --render: the missing pictures are
  // made and every one equals the uninterrupted run's.
  ASSERT_EQ(tear("run " + scene_path + " -o " + path("part") + " -q --frames 2"), 0) << err_;
  ASSERT_EQ(tear("run " + scene_path + " -o " + path("part") + " -q --frames 4 --resume --render" +
                 kSmall + " --no-video"),
            0)
      << err_;
  for (int f : {0, 2, 4}) {
    const std::string name = "/render/0000" + std::to_string(f) + ".png";
    ASSERT_TRUE(fs::exists(path("part") + name)) << name;
    EXPECT_EQ(read_file(path("part") + name), read_file(path("full") + name)) << name;
  }
  EXPECT_FALSE(fs::exists(path("part/preview.mp4")));  // --no-video
}

// --space rest: every particle at its frame-0 position. Coloured by material (the same in every
// frame), a later frame in rest space is frame 0's picture, outside the caption; in world space
// it is not (the disk has fallen and spun).
TEST_F(RenderCli, RestSpaceDrawsEachParticleAtItsFrameZeroPosition) {
  const std::string run = run_folder();
  // One fixed camera (the fitted ones differ: world space also frames where the colliders go,
  // which moves the ground too).
  const std::string opts = std::string(kSmall) +
                           " --color material --no-video -q --camera-position 0.5,0.45,2.5 "
                           "--camera-target 0.5,0.45,0";
  ASSERT_EQ(tear("render " + run + opts + " --space rest"), 0) << err_;
  const Image rest0 = picture(run + "/render/00000.png"), rest4 = picture(run + "/render/00004.png");
  ASSERT_EQ(tear("render " + run + opts), 0) << err_;
  const Image world0 = picture(run + "/render/00000.png"), world4 = picture(run + "/render/00004.png");
  // Below the caption (the top 24 rows) pixel for pixel.
  auto rows = [](const Image& im, int from) {
    return std::vector<uint8_t>(im.rgb.begin() + 3 * from * im.width, im.rgb.end());
  };
  EXPECT_EQ(rows(rest4, 24), rows(rest0, 24));
  EXPECT_NE(rows(world4, 24), rows(world0, 24));
  // --frames without 0 still takes the rest positions from frame 0.
  ASSERT_EQ(tear("render " + run + opts + " --space rest --frames 4"), 0) << err_;
  EXPECT_EQ(rows(picture(run + "/render/00004.png"), 24), rows(rest0, 24));
  // Rest space needs frame 0.
  fs::remove(run + "/frames/00000.ply");
  EXPECT_EQ(tear("render " + run + opts + " --space rest --frames 4"), 1);
  EXPECT_NE(err_.find("no frame 0 to take the rest positions from"), std::string::npos) << err_;
}

// A 2D run without gravity: a small disk and two box colliders away from it, one rising at
// 2.5 per second the whole run, one still and active only until t = 0.05 (frames 0..2 of 0..4).
nlohmann::json two_colliders_scene(nlohmann::json s) {
  s["gravity"] = {0, 0};
  s["objects"][0]["shape"] = {{"type", "sphere"}, {"center", {0.3, 0.5}}, {"radius", 0.08}};
  s["objects"][0]["velocity"] = {0, 0};
  s["objects"][0]["angular_velocity"] = 0;
  s["boundaries"] = nlohmann::json::parse(R"([
    { "type": "sticky", "shape": { "type": "box", "min": [0.55, 0.40], "max": [0.65, 0.50] },
      "velocity": [0, 2.5] },
    { "type": "sticky", "shape": { "type": "box", "min": [0.75, 0.40], "max": [0.85, 0.50] },
      "end": 0.05 } ])");
  return s;
}

// The picture's pixel of a world point under the camera the test gives (the up direction is +y
// without gravity).
std::pair<int, int> pixel_of(const Eigen::Vector3d& p) {
  Camera c;
  c.position = Eigen::Vector3d(0.5, 0.5, 2.5);
  c.target = Eigen::Vector3d(0.5, 0.5, 0);
  c.fov_deg = 40;
  c.width = 240;
  c.height = 160;
  double x = -1, y = -1;
  EXPECT_TRUE(c.project(p, &x, &y));
  return {int(x), int(y)};
}

// The darkest pixel (sum of channels) within a pixel of where a world point is seen.
int darkest_at(const Image& im, double x, double y) {
  const auto [px, py] = pixel_of(Eigen::Vector3d(x, y, 0));
  int darkest = 3 * 255;
  for (int j = py - 1; j <= py + 1; ++j)
    for (int i = px - 1; i <= px + 1; ++i) {
      const uint8_t* c = im.at(i, j);
      darkest = std::min(darkest, int(c[0]) + int(c[1]) + int(c[2]));
    }
  return darkest;
}

// Each collider is drawn (outlined) where it is at each frame's time: the rising box's top edge
// moves up by 2.5 * 0.08 between frames 0 and 4, the other box is gone once inactive.
// --no-colliders changes only the colliders' pixels, and rest-space pictures have none.
TEST_F(RenderCli, CollidersAreDrawnWhereTheyAreAtEachFrame) {
  const std::string run = run_folder(two_colliders_scene(scene()));
  const std::string opts =
      " --width 240 --height 160 --samples 4 --no-video -q --camera-position 0.5,0.5,2.5 "
      "--camera-target 0.5,0.5,0 --fov 40 --frames 0:4";
  ASSERT_EQ(tear("render " + run + opts), 0) << err_;
  const Image f0 = picture(run + "/render/00000.png"), f4 = picture(run + "/render/00004.png");
  constexpr int kDark = 3 * 100, kLight = 3 * 150;  // outline; background, ground, fill
  // The rising box: its top edge at y = 0.5 in frame 0 and 0.7 in frame 4 (17 pixels up).
  EXPECT_LT(darkest_at(f0, 0.6, 0.5), kDark);
  EXPECT_GT(darkest_at(f0, 0.6, 0.7), kLight);
  EXPECT_LT(darkest_at(f4, 0.6, 0.7), kDark);
  EXPECT_GT(darkest_at(f4, 0.6, 0.5), kLight);
  EXPECT_LT(darkest_at(f4, 0.6, 0.6), kDark);  // its bottom edge, where its top was + 0.1
  // The box that stops at t = 0.05: outlined in frame 0, absent in frame 4.
  EXPECT_LT(darkest_at(f0, 0.8, 0.5), kDark);
  EXPECT_GT(darkest_at(f4, 0.8, 0.5), kLight);
  EXPECT_LT(darkest_at(f0, 0.85, 0.45), kDark);  // its right edge
  EXPECT_GT(darkest_at(f4, 0.85, 0.45), kLight);

  // --no-colliders: the same pictures but for the colliders' pixels (within 3 pixels of the
  // boxes of frame 0).
  ASSERT_EQ(tear("render " + run + opts + " --no-colliders"), 0) << err_;
  const Image bare = picture(run + "/render/00000.png");
  EXPECT_GT(darkest_at(bare, 0.6, 0.5), kLight);
  EXPECT_GT(darkest_at(bare, 0.8, 0.5), kLight);
  const auto [x0, y0] = pixel_of(Eigen::Vector3d(0.55, 0.5, 0));
  const auto [x1, y1] = pixel_of(Eigen::Vector3d(0.85, 0.4, 0));
  int inside = 0, outside = 0;
  for (int y = 0; y < bare.height; ++y)
    for (int x = 0; x < bare.width; ++x) {
      if (std::memcmp(bare.at(x, y), f0.at(x, y), 3) == 0) continue;
      const bool near = x >= x0 - 3 && x <= x1 + 3 && y >= y0 - 3 && y <= y1 + 3;
      (near ? inside : outside) += 1;
    }
  EXPECT_GT(inside, 150);
  EXPECT_EQ(outside, 0);

  // Rest space: no colliders to leave out.
  ASSERT_EQ(tear("render " + run + opts + " --space rest"), 0) << err_;
  const std::string rest = read_file(run + "/render/00004.png");
  ASSERT_EQ(tear("render " + run + opts + " --space rest --no-colliders"), 0) << err_;
  EXPECT_EQ(read_file(run + "/render/00004.png"), rest);
}

// output.fields adds driving_force and damage_laplacian to the frames (and only then), and
// tear render colours by them.
TEST_F(RenderCli, DrivingForceAndDamageLaplacianWhenTheSceneWritesThem) {
  json s = scene();
  s["materials"]["jelly"]["damage"] = {{"sigma_c", 5}, {"eta", 0.01}};
  s["output"]["fields"] = {"driving_force", "damage_laplacian"};
  const std::string run = run_folder(s);
  const PointTable last = read_frame(run + "/frames/00004.ply");
  ASSERT_GE(last.names.size(), 2u);
  EXPECT_EQ(last.names[last.names.size() - 2], "driving_force");
  EXPECT_EQ(last.names.back(), "damage_laplacian");
  double most = 0;
  for (double d : last.column("driving_force")) most = std::max(most, d);
  EXPECT_GT(most, 0) << "the fall should drive some damage";
  for (const char* map : {"driving_force", "damage_laplacian"}) {
    ASSERT_EQ(tear("render " + run + kSmall + " --no-video -q --frames 4 --color " + map), 0)
        << err_;
    EXPECT_NE(out_.find(std::string("(96x64, ") + map + ")"), std::string::npos) << out_;
  }
  // And tear run --render draws them as it goes.
  ASSERT_EQ(tear("run " + write_scene(s) + " -o " + path("live") +
                 " -q --frames 1 --render --no-video --color damage_laplacian" + kSmall),
            0)
      << err_;
  EXPECT_TRUE(fs::exists(path("live/render/00001.png")));
}

TEST_F(RenderCli, MissingFfmpegWarnsAndKeepsThePictures) {
  const std::string run = run_folder();
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", "/nonexistent-tear-test", 1);
  const int code = tear("render " + run + kSmall + " -q");
  setenv("PATH", saved.c_str(), 1);
  EXPECT_EQ(code, 0) << err_;
  EXPECT_NE(err_.find("tear: warning: ffmpeg not found on PATH"), std::string::npos) << err_;
  EXPECT_TRUE(fs::exists(run + "/render/00004.png"));
  EXPECT_FALSE(fs::exists(run + "/preview.mp4"));
}

TEST_F(RenderCli, BadInputIsAClearOneLineError) {
  const std::string run = run_folder();
  fs::create_directories(path("empty"));
  fs::create_directories(path("noscene"));
  fs::copy(run + "/frames", path("noscene/frames"));
  struct Case {
    std::string args;
    int code;
    std::string message;
  };
  const Case cases[] = {
      {"render " + path("nowhere"), 1, "tear: " + path("nowhere") + ": no such folder"},
      {"render " + path("empty"), 1, path("empty") + ": no frames/ folder"},
      {"render " + path("noscene"), 1, path("noscene") + "/scene.json: missing"},
      {"render " + run + " --frames 7:", 1, "tear: " + run + ": no frames in --frames 7:"},
      {"render " + run + " --frames 3:1", 2, "--frames \"3:1\": expected A:B"},
      {"render " + run + " --color rainbow", 2, "--color"},
      {"render " + run + " --width 4", 2, "--width"},
      {"render " + run + " --samples 0", 2, "--samples"},
      {"render " + run + " --camera-position 1,2", 2, "--camera-position"},
      {"render " + run + " --camera-up=0,0,0", 1, "--camera-up: must be non-zero"},
      {"render", 2, "dir is required"},
      {"run " + write_scene(scene()) + " -o " + path("x") + " --color damage", 2, "--render"},
      // The optional columns of a run that did not write them (scene output.fields).
      {"render " + run + " --color driving_force", 1,
       "tear: " + run +
           "/frames/00000.ply: no column 'driving_force' for --color driving_force: "
           "the run did not write it (list \"driving_force\" in the scene's output.fields"},
      {"run " + write_scene(scene()) + " -o " + path("x") + " --render --color damage_laplacian", 1,
       "--color damage_laplacian: the run does not write 'damage_laplacian'"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(tear(c.args), c.code) << c.args << "\n" << err_;
    EXPECT_NE(err_.find(c.message), std::string::npos) << c.args << "\n" << err_;
    if (c.code == 1) {
      EXPECT_EQ(std::count(err_.begin(), err_.end(), '\n'), 1) << err_;
    }
  }
  EXPECT_FALSE(fs::exists(path("x")));
  // A frame file that is not a PLY: the file and the reason.
  write_file_atomic(run + "/frames/00002.ply", "garbage");
  EXPECT_EQ(tear("render " + run + kSmall + " --no-video -q"), 1);
  EXPECT_NE(err_.find(run + "/frames/00002.ply"), std::string::npos) << err_;
}

}  // namespace
}  // namespace tear
