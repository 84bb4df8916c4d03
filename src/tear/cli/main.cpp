// cli/: the `tear` executable, a thin layer over driver/ (ARCHITECTURE.md "What a user does").
#include "tear/driver/bench_suite.h"
#include "tear/driver/convert.h"
#include "tear/driver/crack_report.h"
#include "tear/driver/mesh_frames.h"
#include "tear/driver/render_frames.h"
#include "tear/driver/run.h"
#include "tear/exec/memory.h"
#include "tear/scene/scene.h"

#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <CLI/CLI.hpp>

#include <iostream>

namespace {

// The picture options `tear render` and `tear run --render` share.
struct RenderArgs {
  std::vector<CLI::Option*> options;
  std::string color;
  int width = 0, height = 0, samples = 0;
  bool surface = false, no_video = false, no_colliders = false;
  std::string space = "world";
  std::vector<double> position, target, up;
  double fov = 0, radius = 0, color_max = 0;

  void add(CLI::App* cmd) {
    auto keep = [&](CLI::Option* o) { options.push_back(o); };
    keep(cmd->add_option("--color", color,
                         "Colour by damage, material, fibers, velocity, driving_force or "
                         "damage_laplacian (the last two where the scene's output.fields wrote "
                         "them; default: the scene's render.color, damage)")
             ->check(CLI::IsMember(std::vector<std::string>(std::begin(tear::RenderSpec::kColors),
                                                            std::end(tear::RenderSpec::kColors)))));
    keep(cmd->add_flag("--surface", surface,
                       "Draw the surface mesh of the particles instead of spheres"));
    using tear::RenderSpec;
    const RenderSpec def;
    keep(cmd->add_option("--width", width,
                         "Picture width in pixels (default " + std::to_string(def.width) + ")")
             ->check(CLI::Range(RenderSpec::kMinSize, RenderSpec::kMaxSize)));
    keep(cmd->add_option("--height", height,
                         "Picture height in pixels (default " + std::to_string(def.height) + ")")
             ->check(CLI::Range(RenderSpec::kMinSize, RenderSpec::kMaxSize)));
    keep(cmd->add_option("--samples", samples,
                         "Samples per pixel (default " + std::to_string(def.samples) + ")")
             ->check(CLI::Range(1, RenderSpec::kMaxSamples)));
    keep(cmd->add_option("--camera-position", position,
                         "Camera position x,y,z (default: fitted to the first frame)")
             ->delimiter(',')
             ->expected(3));
    keep(cmd->add_option("--camera-target", target,
                         "Point the camera looks at, x,y,z (default: the first frame's centre)")
             ->delimiter(',')
             ->expected(3));
    keep(cmd->add_option("--camera-up", up, "Camera up direction x,y,z (default: against gravity)")
             ->delimiter(',')
             ->expected(3));
    keep(cmd->add_option("--fov", fov, "Vertical field of view in degrees (default 40)")
             ->check(CLI::Range(0.01, 179.0)));
    keep(cmd->add_option("--radius", radius,
                         "Sphere radius of every particle (default: half the particle spacing)")
             ->check(CLI::PositiveNumber));
    keep(cmd->add_option("--color-max,--velocity-max", color_max,
                         "Top of the velocity or driving_force colour map, or the ends +-V of "
                         "damage_laplacian's (default: fitted to the frames)")
             ->check(CLI::PositiveNumber));
    keep(cmd->add_flag("--no-colliders", no_colliders,
                       "Leave the colliders out of the pictures (drawn translucent by default)"));
    keep(cmd->add_flag("--no-video", no_video, "Write the pictures only, no preview.mp4"));
    keep(cmd->add_option("--space", space,
                         "world (default): particles where they are; rest: each particle at its "
                         "frame-0 position, coloured as in the frame (damage in material space)")
             ->check(CLI::IsMember({"world", "rest"})));
  }

  tear::RenderOverrides overrides() const {
    tear::RenderOverrides o;
    auto given = [&](const char* name) {
      for (const CLI::Option* opt : options)
        if (opt->get_name() == name) return opt->count() > 0;
      return false;
    };
    auto vec = [](const std::vector<double>& v) { return Eigen::Vector3d(v[0], v[1], v[2]); };
    if (given("--color")) o.color = color;
    if (given("--width")) o.width = width;
    if (given("--height")) o.height = height;
    if (given("--samples")) o.samples = samples;
    o.surface = surface;
    if (given("--camera-position")) o.camera_position = vec(position);
    if (given("--camera-target")) o.camera_target = vec(target);
    if (given("--camera-up")) o.camera_up = vec(up);
    if (given("--fov")) o.fov_deg = fov;
    if (given("--radius")) o.radius = radius;
    if (given("--color-max")) o.color_max = color_max;
    o.colliders = !no_colliders;
    o.video = !no_video;
    o.rest_space = space == "rest";
    return o;
  }
};

}  // namespace

int main(int argc, char** argv) {
#ifdef __GLIBC__
  // A step allocates and frees scratch arrays of several MiB (grid-sized tables, the implicit
  // solve's Hessian, the inextensibility rows). glibc would hand each back to the kernel and
  // fault its pages in again on the next step: half the run time of the inextensible disk tear
  // (11.1 s -> 5.4 s for 3 frames). Keep freed memory in the process instead.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  CLI::App app{"tear: anisotropic tearing and fracture with the Material Point Method"};
  app.set_version_flag("--version", std::string("tear ") + TEAR_VERSION);
  app.require_subcommand(1);
  app.footer("Exit codes: 0 success, 1 bad input or a failed run (one line on stderr),\n"
             "2 command-line usage error, 3 the simulation blew up, 130/143 stopped by\n"
             "SIGINT/SIGTERM after writing a checkpoint (--resume continues).\n"
             "Documentation: docs/cli.md, docs/long-runs.md");

  tear::RunOptions run;
  CLI::App* run_cmd = app.add_subcommand("run", "Simulate a scene; write frames and statistics");
  run_cmd->add_option("scene", run.scene_path, "Scene file (JSON)")->required();
  run_cmd->add_option("-o,--out", run.out_dir, "Output folder")->required();
  run_cmd->add_option("--threads", run.threads, "Worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--frames", run.frames, "Override time.frames")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--set", run.overrides,
                      "Override a scene value: dotted.path=VALUE (VALUE is JSON or a string)")
      ->take_all()
      ->allow_extra_args(false);
  const char* resolution_help =
      "Refine the grid K times: grid.dx and time.max_dt divided by K (l0 follows dx unless "
      "the scene sets it); K < 1 coarsens";
  run_cmd->add_option("--resolution", run.resolution, resolution_help)
      ->check(CLI::PositiveNumber);
  run_cmd->add_flag("-q,--quiet", run.quiet, "No progress line");
  run_cmd->add_flag("--resume", run.resume,
                    "Continue the run in --out from its checkpoint (from frame 0 if it has none)");
  std::string max_memory;
  run_cmd->add_option("--max-memory", max_memory,
                      "Refuse a run whose memory estimate (tear check) is larger: 16G, 512M, ... "
                      "(0: no limit; default: 90% of this machine's memory)")
      ->check([](const std::string& text) {
        try {
          tear::parse_size(text);
          return std::string();
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
      });
  CLI::Option* render_flag = run_cmd->add_flag(
      "--render", run.render,
      "Render each written frame into DIR/render/ and make DIR/preview.mp4 (options as for "
      "tear render)");
  RenderArgs run_render;
  run_render.add(run_cmd);
  for (CLI::Option* o : run_render.options) o->needs(render_flag);

  std::string check_path;
  std::vector<std::string> check_overrides;
  CLI::App* check_cmd =
      app.add_subcommand("check", "Validate a scene and print what a run would do");
  check_cmd->add_option("scene", check_path, "Scene file (JSON)")->required();
  check_cmd->add_option("--set", check_overrides, "Override a scene value: dotted.path=VALUE")
      ->allow_extra_args(false);
  double check_resolution = 1;
  check_cmd->add_option("--resolution", check_resolution, resolution_help)
      ->check(CLI::PositiveNumber);

  CLI::App* info_cmd = app.add_subcommand("info", "Version, build options, libraries, threads");

  tear::RenderOptions render;
  RenderArgs render_args;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Ray trace a run's frames into DIR/render/NNNNN.png and DIR/preview.mp4");
  render_cmd->add_option("dir", render.dir, "Output folder of tear run")->required();
  render_cmd->add_option("--frames", render.frames,
                         "Frames to render: A:B, A:, :B or A (default: all)");
  render_cmd->add_option("--threads", render.threads, "Worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber);
  render_cmd->add_flag("-q,--quiet", render.quiet, "No progress lines");
  render_args.add(render_cmd);

  tear::ConvertOptions convert;
  CLI::App* convert_cmd = app.add_subcommand(
      "convert", "Write a run's frames in another format (particles: ply, bgeo, vtu; meshes: ply, obj, vtu)");
  convert_cmd->add_option("dir", convert.dir, "Output folder of tear run")->required();
  convert_cmd->add_option("--to", convert.format, "Target format: ply, bgeo or vtu (particles); ply, obj or vtu (cloth, yarn and hair meshes)")
      ->required();
  convert_cmd->add_option("--frames", convert.frames,
                          "Frames to convert: A:B, A:, :B or A (default: all)");

  tear::MeshFramesOptions mesh;
  CLI::App* mesh_cmd = app.add_subcommand(
      "mesh", "Surface meshes of a run's frames into DIR/meshes/NNNNN.obj (cracks open)");
  mesh_cmd->add_option("dir", mesh.dir, "Output folder of tear run")->required();
  mesh_cmd->add_option("--frames", mesh.frames, "Frames to mesh: A:B, A:, :B or A (default: all)");
  mesh_cmd->add_option("--spacing", mesh.spacing,
                       "Particle spacing (default: dx / ppc^(1/dim) from DIR/scene.json, else "
                       "the median nearest-neighbour distance in the first frame)")
      ->check(CLI::PositiveNumber);
  mesh_cmd->add_option("--radius", mesh.radius,
                       "Sphere radius per particle, in spacings (default 1)")
      ->check(CLI::PositiveNumber);
  mesh_cmd->add_option("--voxel", mesh.voxel, "Voxel size, in spacings (default 0.5)")
      ->check(CLI::PositiveNumber);
  mesh_cmd->add_option("--smooth", mesh.smooth, "Smoothing passes over the level set (default 2)")
      ->check(CLI::Range(0, 100));
  mesh_cmd->add_option("--damage-threshold", mesh.damage_threshold,
                       "Particles with more damage open the surface")
      ->capture_default_str();
  mesh_cmd->add_option("--format", mesh.formats, "obj, ply or obj,ply")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::IsMember({"obj", "ply"}));
  mesh_cmd->add_option("--threads", mesh.threads, "Worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber);
  mesh_cmd->add_flag("-q,--quiet", mesh.quiet, "No progress lines");

  tear::CrackReportOptions cracks;
  CLI::App* cracks_cmd = app.add_subcommand(
      "cracks", "Crack figures of a run's frames in rest space: cracked share, direction, width");
  cracks_cmd->add_option("dir", cracks.dir, "Output folder of tear run")->required();
  cracks_cmd->add_option("--frames", cracks.frames,
                         "Frames to measure: A:B, A:, :B or A (default: all)");
  cracks_cmd->add_option("--threshold", cracks.threshold, "Cracked: damage above this")
      ->capture_default_str();
  cracks_cmd->add_option("--spacing", cracks.spacing,
                         "Particle spacing (default: dx / ppc^(1/dim) from DIR/scene.json, else "
                         "the median nearest-neighbour distance in frame 0)")
      ->check(CLI::PositiveNumber);
  cracks_cmd->add_flag("--json", cracks.json, "One JSON object per frame");

  long stress_evals = 10000000, particles = 475000;
  int steps = 20;
  std::vector<int> thread_counts{1, 2};
  bool quick = false, no_damage = false;
  CLI::App* bench_cmd = app.add_subcommand("bench", "Benchmark suite; JSON figures on stdout");
  bench_cmd->add_option("--stress-evals", stress_evals, "Stress evaluations per model")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench_cmd->add_option("--particles", particles, "Particles in the step benchmark block")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench_cmd->add_option("--steps", steps, "Timed steps")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench_cmd->add_option("--threads-list", thread_counts, "Thread counts for the step benchmark")
      ->capture_default_str()
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  bench_cmd->add_flag("--no-damage", no_damage,
                      "Skip the damage benchmark (step cost with explicit and implicit damage)");
  bench_cmd->add_flag("--quick", quick,
                      "Small sizes, seconds in all: 1e5 evaluations, 20000 particles, 5 steps");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  if (*run_cmd) {
    run.render_options = run_render.overrides();
    if (!max_memory.empty()) run.max_memory = tear::parse_size(max_memory);
    return tear::run_scene(run);
  }
  if (*render_cmd) {
    render.overrides = render_args.overrides();
    return tear::render_frames(render);
  }
  if (*convert_cmd) return tear::convert_run(convert);
  if (*mesh_cmd) return tear::mesh_frames(mesh);
  if (*cracks_cmd) return tear::crack_report(cracks);
  if (*check_cmd)
    return tear::check_scene(check_path, check_overrides, check_resolution, std::cout);
  if (*info_cmd) {
    tear::print_info(std::cout);
    return 0;
  }
  if (*bench_cmd) {
    if (quick) stress_evals = 100000, particles = 20000, steps = 5;
    try {
      nlohmann::json out;
      std::cerr << "stress evaluation: " << stress_evals << " x 2 models...\n";
      out["stress"] = tear::bench_stress(stress_evals);
      out["step"] = nlohmann::json::array();
      for (int t : thread_counts) {
        std::cerr << "explicit step: " << particles << " particles, " << steps << " steps, " << t
                  << " thread(s)...\n";
        out["step"].push_back(tear::bench_step(particles, steps, t));
      }
      if (!no_damage) {
        const int t = thread_counts.back();
        std::cerr << "damage step (none, explicit, implicit): " << particles << " particles, "
                  << steps << " steps, " << t << " thread(s)...\n";
        out["damage"] = tear::bench_damage(particles, steps, t);
      }
      {
        const int t = thread_counts.back();
        const long cloth = quick ? 15000 : 150000;
        std::cerr << "cloth and hair (" << cloth << " sheet particles, 10000 hair segments) "
                  << "beside solids: " << steps << " steps, " << t << " thread(s)...\n";
        out["codim"] = tear::bench_codim(cloth, steps, t);
      }
      std::cout << out.dump(2) << std::endl;
      return 0;
    } catch (const std::exception& e) {
      std::cerr << "tear: bench: " << e.what() << "\n";
      return 1;
    }
  }
  return 2;
}
