// cli/: the `tear` executable, a thin layer over driver/ (ARCHITECTURE.md "What a user does").
#include "tear/driver/bench_suite.h"
#include "tear/driver/run.h"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"tear: anisotropic tearing and fracture with the Material Point Method"};
  app.set_version_flag("--version", std::string("tear ") + TEAR_VERSION);
  app.require_subcommand(1);
  app.footer("Exit codes: 0 success, 1 bad input or a failed run (one line on stderr),\n"
             "2 command-line usage error. Documentation: docs/cli.md");

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
  run_cmd->add_flag("-q,--quiet", run.quiet, "No progress line");
  run_cmd->add_flag("--resume", run.resume, "Continue the run in --out from its checkpoint");

  std::string check_path;
  std::vector<std::string> check_overrides;
  CLI::App* check_cmd =
      app.add_subcommand("check", "Validate a scene and print what a run would do");
  check_cmd->add_option("scene", check_path, "Scene file (JSON)")->required();
  check_cmd->add_option("--set", check_overrides, "Override a scene value: dotted.path=VALUE")
      ->allow_extra_args(false);

  CLI::App* info_cmd = app.add_subcommand("info", "Version, build options, libraries, threads");

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

  if (*run_cmd) return tear::run_scene(run);
  if (*check_cmd) return tear::check_scene(check_path, check_overrides, std::cout);
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
      std::cout << out.dump(2) << std::endl;
      return 0;
    } catch (const std::exception& e) {
      std::cerr << "tear: bench: " << e.what() << "\n";
      return 1;
    }
  }
  return 2;
}
