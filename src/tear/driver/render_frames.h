// driver/: `tear render` and the rendering behind `tear run --render`: the renderer's settings
// from the scene's "render" section with the command line's overrides, DIR/render/NNNNN.png
// for each frame, and DIR/preview.mp4 through ffmpeg (docs/outputs.md).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tear {

struct Scene;
struct PointTable;
struct MeshPart;

// Command-line options that override the scene's "render" section (unset: the scene's value).
struct RenderOverrides {
  std::optional<std::string> color;  // a RenderSpec::kColors name
  std::optional<int> width, height, samples;
  bool surface = false;  // --surface (the scene's render.surface otherwise)
  std::optional<Eigen::Vector3d> camera_position, camera_target, camera_up;
  std::optional<double> fov_deg;
  std::optional<double> radius;        // sphere radius of every particle
  std::optional<double> color_max;     // fixes the top (range) of the velocity, driving-force and
                                       // damage-Laplacian maps
  bool video = true;                   // false: --no-video
  bool rest_space = false;             // --space rest: particles at their frame-0 positions
  bool colliders = true;               // false: --no-colliders
};

struct RenderOptions {
  std::string dir;     // a run folder
  std::string frames;  // "A:B", "A:", ":B", "A" or "" (all)
  RenderOverrides overrides;
  int threads = 0;  // 0: all cores
  bool quiet = false;
};

// `tear render`. Returns the exit code (1: bad input, 2: a malformed --frames); errors are one
// line "tear: reason" on stderr, progress goes to stderr and a summary to stdout.
int render_frames(const RenderOptions& options);

// Renders the frames of `tear run --render` as the run writes them, with the camera fitted on
// frame 0 and where the colliders go (later frames are not known yet), and makes the video at
// the end.
class RunRenderer {
 public:
  // Validates the settings (throws std::runtime_error on a bad override) before the run
  // writes anything.
  RunRenderer(const std::string& dir, const Scene& scene, const RenderOverrides& overrides,
              int threads);
  ~RunRenderer();
  // A fresh run: removes DIR/render and DIR/preview.mp4 of an earlier run.
  void clear();
  // A resumed run: fits the camera on DIR's frame 0 and renders the frames up to `frame` that
  // have no picture yet.
  void resume(int frame);
  // DIR/render/NNNNN.png of a frame the run has just written, with its codimensional meshes.
  void render(int frame, const PointTable& table, const std::vector<MeshPart>& meshes);
  // DIR/preview.mp4 of every rendered frame of the run; returns what to print.
  std::string finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tear
