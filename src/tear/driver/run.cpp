#include "tear/driver/run.h"

#include "tear/damage/driving_force.h"
#include "tear/driver/command.h"
#include "tear/driver/convert.h"
#include "tear/exec/memory.h"
#include "tear/exec/phase_timer.h"
#include "tear/exec/threads.h"
#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"
#include "tear/io/vtu.h"
#include "tear/driver/simulation.h"
#include "tear/render/render.h"
#include "tear/render/video.h"
#include "tear/surface/mesher.h"
#include "tear/scene/scene.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <type_traits>

#include <signal.h>
#include <unistd.h>

namespace tear {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// A graceful stop (docs/long-runs.md): SIGINT and SIGTERM set `stop_requested`; the run finishes
// the step in progress, writes a checkpoint and exits 130 or 143. The handlers are installed
// with SA_RESETHAND, so a second signal ends the process at once (the last checkpoint stays).
std::atomic<bool> stop_requested{false};
volatile std::sig_atomic_t stop_signal = 0;
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

void on_stop_signal(int sig) {
  stop_signal = sig;
  stop_requested.store(true);
  static const char kText[] =
      "\ntear: stopping after this step to write a checkpoint (signal again to quit at once)\n";
  const ssize_t written = ::write(STDERR_FILENO, kText, sizeof(kText) - 1);
  (void)written;
}

// The handlers for the life of one run; the ones before are restored after it.
class StopSignals {
 public:
  StopSignals() {
    stop_requested = false;
    stop_signal = 0;
    struct sigaction a {};
    a.sa_handler = on_stop_signal;
    sigemptyset(&a.sa_mask);
    a.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &a, &old_int_);
    sigaction(SIGTERM, &a, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// Writes a run's frames: every format the scene asks for, from rows made as the encoder reads
// them, into one buffer kept for the whole run (a frame is tens of MB, and fresh pages cost
// more than writing them); with vtu, DIR/frames.pvd lists each frame at its time.
class FrameWriter {
 public:
  FrameWriter(std::string dir, std::vector<std::string> formats,
              std::vector<std::string> mesh_formats)
      : dir_(std::move(dir)), formats_(std::move(formats)), mesh_formats_(std::move(mesh_formats)) {}
  // A resumed run: the times of the frames written before (frames.pvd lists them too).
  void resume(std::map<int, double> vtu_times) { vtu_times_ = std::move(vtu_times); }

  void write(int frame, const Simulation& sim) {
    const PointRows rows = sim.frame_rows();
    for (const std::string& f : formats_) {
      encode_points(rows, f, &buffer_, &table_);
      write_file_atomic(frame_path(dir_, frame, f), buffer_);
    }
    // The meshes (cloth, yarn, hair, FEM surfaces and volumes): a file per part and mesh format;
    // with vtu, DIR/PART.pvd lists them at their times.
    const std::vector<MeshPart> parts = sim.frame_meshes();
    vtu_times_[frame] = sim.time();
    for (const MeshPart& part : parts)
      for (const std::string& f : mesh_part_formats_of(part, mesh_formats_)) {
        write_file_atomic(mesh_part_path(dir_, frame, part.name, f), encode_mesh_part(part, f));
        if (f == "vtu") write_mesh_part_pvd(dir_, part.name, vtu_times_);
      }
    if (std::find(formats_.begin(), formats_.end(), "vtu") != formats_.end()) {
      write_frames_pvd(dir_, vtu_times_);
    }
  }

 private:
  std::string dir_;
  std::vector<std::string> formats_, mesh_formats_;
  std::map<int, double> vtu_times_;  // the times of the frames written so far
  std::string buffer_;
  PointTable table_;  // for the formats written column by column
};

// For choosing sigma_c: the uniaxial stretch (other directions held) at which a particle of
// the material starts to crack, across and along its primary fiber.
void print_crack_onset(std::ostream& out, const Scene& s, const MaterialSpec& m) {
  const Real alpha[2] = {Real(m.damage.alpha[0]), Real(m.damage.alpha[1])};
  Real across = 0, along = 0;
  auto onsets = [&](auto dim) {
    constexpr int Dim = decltype(dim)::value;
    using V = Vec<Dim>;
    const Mat<Dim> D = Mat<Dim>::Identity();  // primary fiber along x
    across = crack_onset_stretch<Dim>(m.params, D, alpha, Real(m.damage.sigma_c), V::Unit(1));
    along = crack_onset_stretch<Dim>(m.params, D, alpha, Real(m.damage.sigma_c), V::Unit(0));
  };
  if (s.dim == 2)
    onsets(std::integral_constant<int, 2>{});
  else
    onsets(std::integral_constant<int, 3>{});
  auto text = [](Real stretch) {
    if (std::isinf(stretch)) return std::string("beyond 4");
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.4g", double(stretch));
    return std::string(buf);
  };
  out << "damage     " << m.name << ": sigma_c " << m.damage.sigma_c << ", eta " << m.damage.eta
      << ", alpha [" << m.damage.alpha[0] << ", " << m.damage.alpha[1] << "]";
  if (m.damage.anisotropic_surface())
    out << ", surface_anisotropy [" << m.damage.surface[0] << ", " << m.damage.surface[1] << "]";
  out << "; cracks start at a uniaxial stretch of " << text(across) << " across the fibers, "
      << text(along) << " along them (other directions held)\n";
}

// Simulated time with three decimals, or three significant digits for tiny frame times.
std::string time_text(double t) {
  char buf[32];
  if (t == 0 || std::abs(t) >= 1e-2)
    std::snprintf(buf, sizeof(buf), "%.3fs", t);
  else
    std::snprintf(buf, sizeof(buf), "%.3gs", t);
  return buf;
}

// One status line on stderr, "frame 12/48  t=0.500s  steps/s 1234  ETA 0:35": rewritten in
// place behind a bar on a terminal, printed as a plain line every ~5% of the frames otherwise
// (log files and pipes get no carriage returns).
class Progress {
 public:
  Progress(bool enabled, int total_frames, int first_frame)
      : enabled_(enabled),
        tty_(::isatty(STDERR_FILENO) != 0),
        total_(total_frames),
        first_(first_frame),
        start_(Clock::now()) {}

  void update(int frame, double sim_time, long steps_done) {
    if (!enabled_) return;
    const double wall = std::chrono::duration<double>(Clock::now() - start_).count();
    const int done = frame - first_;
    const double eta = done > 0 ? wall / done * (total_ - frame) : NAN;
    const double rate = wall > 0 ? double(steps_done) / wall : 0;
    char line[256];
    std::snprintf(line, sizeof(line), "frame %d/%d  t=%s  steps/s %.0f  ETA %s", frame, total_,
                  time_text(sim_time).c_str(), rate, clock_text(eta).c_str());
    if (tty_) {
      constexpr int kWidth = 24;
      const int filled = total_ > 0 ? std::clamp(kWidth * frame / total_, 0, kWidth) : kWidth;
      std::fprintf(stderr, "\r[%s%s] %s\033[K", std::string(size_t(filled), '#').c_str(),
                   std::string(size_t(kWidth - filled), ' ').c_str(), line);
      if (frame == total_) std::fputc('\n', stderr);
    } else {
      const int every = std::max(1, total_ / 20);
      if (frame == total_ || (frame - first_) % every == 0) std::fprintf(stderr, "%s\n", line);
    }
    std::fflush(stderr);
  }

 private:
  bool enabled_, tty_;
  int total_, first_;
  Clock::time_point start_;
};

Scene load(const std::string& path, std::vector<std::string> overrides, int frames,
           double resolution) {
  if (frames >= 0) overrides.push_back("time.frames=" + std::to_string(frames));
  return load_scene(path, overrides, resolution);
}

// The parts of a resolved scene that a resumed run must keep: all but time.frames (it may
// grow), and the keys that change no simulation result (the description, the render section
// and how often checkpoints are written).
nlohmann::json resume_relevant(nlohmann::json j) {
  if (j.contains("time") && j["time"].is_object()) j["time"].erase("frames");
  if (j.contains("output") && j["output"].is_object()) j["output"].erase("checkpoint_every");
  j.erase("render");
  j.erase("description");
  // Keys that scenes resolved before they existed lack, at the value that changes nothing: a
  // run begun then resumes (objects' "kind", the mesh formats).
  if (j.contains("output") && j["output"].is_object() &&
      j["output"].value("mesh_formats", nlohmann::json::array({"ply"})) ==
          nlohmann::json::array({"ply"}))
    j["output"].erase("mesh_formats");
  if (j.contains("objects") && j["objects"].is_array())
    for (nlohmann::json& o : j["objects"])
      if (o.is_object() && o.value("kind", "volume") == "volume") o.erase("kind");
  return j;
}

// The first key (as a dotted path, array entries by index) where two JSON values differ, with
// both values, e.g. "materials.jelly.E (was 500, now 600)"; empty when equal.
std::string first_difference(const nlohmann::json& was, const nlohmann::json& now,
                             const std::string& path = "") {
  if (was == now) return "";
  const auto at = [&](const std::string& key) { return path.empty() ? key : path + "." + key; };
  if (was.is_object() && now.is_object()) {
    for (auto it = was.begin(); it != was.end(); ++it) {
      if (!now.contains(it.key()))
        return at(it.key()) + " (was " + it.value().dump() + ", now absent)";
      const std::string d = first_difference(it.value(), now[it.key()], at(it.key()));
      if (!d.empty()) return d;
    }
    for (auto it = now.begin(); it != now.end(); ++it)
      if (!was.contains(it.key()))
        return at(it.key()) + " (was absent, now " + it.value().dump() + ")";
  }
  if (was.is_array() && now.is_array() && was.size() == now.size()) {
    for (size_t i = 0; i < was.size(); ++i) {
      const std::string d = first_difference(was[i], now[i], path + "[" + std::to_string(i) + "]");
      if (!d.empty()) return d;
    }
  }
  return (path.empty() ? std::string("the scene") : path) + " (was " + was.dump() + ", now " +
         now.dump() + ")";
}

// The stats lines of an earlier run up to and including `frame`.
std::vector<std::string> stats_up_to(const std::string& path, int frame) {
  std::vector<std::string> kept;
  std::istringstream in(read_file(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (nlohmann::json::parse(line).at("frame").get<int>() <= frame) kept.push_back(line);
  }
  return kept;
}

// Writes a checkpoint. The one before becomes checkpoints/previous.bin first, so that a complete
// checkpoint is on disk at every moment: a run killed between the two steps leaves
// previous.bin, and --resume falls back to it.
void write_checkpoint(const std::string& latest, const std::string& previous,
                      const ByteWriter& bytes) {
  if (fs::exists(latest)) fs::rename(latest, previous);
  write_file_atomic(latest, bytes);
}

// For an error message once a checkpoint of the run is on disk.
std::string kept_text(const Simulation& sim) {
  return "; the last good checkpoint (frame " + std::to_string(sim.frame()) + ", t = " +
         time_text(sim.time()) + ") is kept: --resume continues from it";
}

// The run's folders where an interrupted write may have left a temporary.
void remove_stale_temporaries_in(const fs::path& dir) {
  for (const char* sub : {"", "frames", "checkpoints", "render", "meshes"})
    remove_stale_temporaries((dir / sub).string());
}

}  // namespace

int run_scene(const RunOptions& o) {
  // What an error message adds once the run has written a checkpoint.
  std::string kept;
  try {
    const auto limit = limit_threads(o.threads);
    const StopSignals signals;
    const Clock::time_point start = Clock::now();
    // Everything that can be wrong with the input is found before anything is written.
    const Scene scene = load(o.scene_path, o.overrides, o.frames, o.resolution);
    std::unique_ptr<Simulation> sim = make_simulation(scene);
    const double memory = double(sim->memory_bytes());
    const double max_memory = o.max_memory >= 0 ? o.max_memory : 0.9 * physical_memory_bytes();
    if (max_memory > 0 && memory > max_memory)
      return fail(o.scene_path + ": the run needs about " + size_text(memory) +
                  " (tear check), more than " +
                  (o.max_memory >= 0 ? "--max-memory " : "90 % of this machine's memory, ") +
                  size_text(max_memory) +
                  "; coarsen the scene (grid.dx, objects[].ppc, --resolution) or set "
                  "--max-memory (0: no limit)");
    std::unique_ptr<RunRenderer> renderer;
    if (o.render)
      renderer = std::make_unique<RunRenderer>(o.out_dir, scene, o.render_options, o.threads);
    const fs::path dir(o.out_dir);
    const std::string stats_path = (dir / "stats.jsonl").string();
    const std::string checkpoint_path = (dir / "checkpoints" / "latest.bin").string();
    const std::string previous_path = (dir / "checkpoints" / "previous.bin").string();
    std::vector<std::string> stats;
    FrameWriter frames(o.out_dir, scene.formats, scene.mesh_formats);

    const std::string old_scene = (dir / "scene.json").string();
    bool resume = o.resume;
    if (resume) {
      if (!fs::exists(old_scene)) return fail(old_scene + ": no earlier run to resume");
      const std::string differs =
          first_difference(resume_relevant(nlohmann::json::parse(read_file(old_scene))),
                           resume_relevant(scene.resolved));
      if (!differs.empty())
        return fail(old_scene + ": scene differs from " + o.scene_path + " at " + differs +
                    "; a resume may change only time.frames, description, render and "
                    "output.checkpoint_every; run without --resume into a fresh folder");
      if (!fs::exists(checkpoint_path) && !fs::exists(previous_path)) {
        // Stopped before its first checkpoint: the same scene again from the start.
        std::fprintf(stderr, "tear: %s has no checkpoint yet; starting from frame 0\n",
                     o.out_dir.c_str());
        resume = false;
      }
    }
    // What a killed run was writing (".NAME.tmp.PID"): never a file the run reads.
    remove_stale_temporaries_in(dir);
    if (resume) {
      // The latest checkpoint, or the one before it where the latest is missing or damaged
      // (set aside as checkpoints/damaged.bin, so that the next checkpoint cannot push the
      // good one out).
      std::string latest_error;
      try {
        sim->decode_checkpoint(read_file(checkpoint_path));
      } catch (const std::exception& e) {
        latest_error = checkpoint_path + ": " + e.what();
      }
      if (!latest_error.empty()) {
        if (!fs::exists(previous_path)) return fail(latest_error);
        sim = make_simulation(scene);
        try {
          sim->decode_checkpoint(read_file(previous_path));
        } catch (const std::exception& e) {
          return fail(latest_error + "; " + previous_path + ": " + e.what());
        }
        const bool set_aside = fs::exists(checkpoint_path);
        if (set_aside) fs::rename(checkpoint_path, dir / "checkpoints" / "damaged.bin");
        std::fprintf(stderr, "tear: warning: %s; resuming from %s (frame %d) instead%s\n",
                     latest_error.c_str(), previous_path.c_str(), sim->frame(),
                     set_aside ? " (the damaged one is kept as checkpoints/damaged.bin)" : "");
      }
      kept = kept_text(*sim);
      if (sim->frame() >= scene.frames) {
        std::printf("%s: already complete (%d frames)\n", o.out_dir.c_str(), sim->frame());
        return 0;
      }
      if (!fs::exists(stats_path)) return fail(stats_path + ": missing; cannot resume");
      stats = stats_up_to(stats_path, sim->frame());
      frames.resume(frame_times(stats));
      // Record the new frame count; everything else was checked to be equal.
      write_file_atomic(old_scene, scene.resolved.dump(2) + "\n");
      if (renderer) renderer->resume(sim->frame());
      if (!o.quiet)
        std::fprintf(stderr, "resuming %s at frame %d (t = %g s)\n", o.out_dir.c_str(),
                     sim->frame(), sim->time());
    } else {
      // A fresh run owns scene.json, stats.jsonl, frames/, frames.pvd and checkpoints/ in the
      // folder.
      fs::remove_all(dir / "frames");
      fs::remove_all(dir / "checkpoints");
      fs::remove(dir / "frames.pvd");
      for (const char* part : {"surfaces.pvd", "curves.pvd"}) fs::remove(dir / part);
      make_directories((dir / "frames").string());
      write_file_atomic((dir / "scene.json").string(), scene.resolved.dump(2) + "\n");
      frames.write(0, *sim);
      if (renderer) {
        renderer->clear();
        renderer->render(0, sim->frame_table(), sim->frame_meshes());
      }
      FrameStats s = sim->collect_stats();
      stats.push_back(s.to_json().dump());
      write_lines_atomic(stats_path, stats);
    }
    make_directories((dir / "checkpoints").string());

    Progress progress(!o.quiet, scene.frames, sim->frame());
    const long steps_before = sim->total_steps();
    bool warned_unconverged = false;
    // Where the run's time goes (the summary line at the end).
    double setup_s = seconds_since(start), stepping_s = 0, stats_s = 0, output_s = 0;
    // Checkpoints keep the previous one until the new one is complete; `kept` tells an error
    // message which frame a --resume would continue from.
    auto checkpoint = [&] {
      write_checkpoint(checkpoint_path, previous_path, sim->checkpoint());
      kept = kept_text(*sim);
    };
    // A stop requested by a signal: checkpoint where the run is (mid-frame too) and say so.
    auto stop = [&](bool checkpoint_written) {
      if (!checkpoint_written) checkpoint();
      const int sig = stop_signal;
      std::fprintf(stderr,
                   "tear: stopped by %s at t = %s (%d of %d frames done); checkpoint written: "
                   "continue with --resume\n",
                   sig == SIGTERM ? "SIGTERM" : "SIGINT", time_text(sim->time()).c_str(),
                   sim->frame(), scene.frames);
      return sig == SIGTERM ? kExitTerminated : kExitInterrupted;
    };
    while (sim->frame() < scene.frames) {
      bool frame_done;
      {
        PhaseTimer timer(&stepping_s);
        frame_done = sim->advance_frame(&stop_requested);
      }
      if (!frame_done) return stop(false);
      const int frame = sim->frame();
      const auto stats_start = Clock::now();
      FrameStats s = sim->collect_stats();
      stats_s += seconds_since(stats_start);
      const auto output_start = Clock::now();
      s.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
      if (s.damage_unconverged > 0 && !warned_unconverged) {
        std::fprintf(stderr,
                     "tear: warning: frame %d: %ld implicit damage solve(s) stopped at "
                     "damage.max_iterations = %d with a last change of %.3g > damage.tolerance "
                     "%.3g (stats.jsonl: damage_unconverged, damage_change); shown once\n",
                     frame, s.damage_unconverged, scene.damage.max_iterations, s.damage_change,
                     scene.damage.tolerance);
        warned_unconverged = true;
      }
      if (frame % scene.output_every == 0 || frame == scene.frames) {
        frames.write(frame, *sim);
        if (renderer) renderer->render(frame, sim->frame_table(), sim->frame_meshes());
      }
      stats.push_back(s.to_json().dump());
      write_lines_atomic(stats_path, stats);
      const bool checkpointed =
          (scene.checkpoint_every > 0 && frame % scene.checkpoint_every == 0) ||
          frame == scene.frames;
      if (checkpointed) checkpoint();
      output_s += seconds_since(output_start);
      progress.update(frame, sim->time(), sim->total_steps() - steps_before);
      if (stop_requested && frame < scene.frames) return stop(checkpointed);
    }
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    std::printf("wrote %d frames (%zu particles, %ld steps) to %s in %.1f s\n", scene.frames,
                sim->num_particles(), sim->total_steps(), o.out_dir.c_str(), wall);
    std::string phases;
    for (const auto& [name, seconds] : sim->phase_seconds()) {
      if (seconds == 0) continue;
      char buf[64];
      std::snprintf(buf, sizeof(buf), "%s%s %.1f", phases.empty() ? "" : ", ", name.c_str(), seconds);
      phases += buf;
    }
    std::printf("time: %.1f s stepping (%s), %.1f s writing frames and checkpoints%s, %.1f s "
                "statistics, %.1f s loading, sampling and the first frame\n",
                stepping_s, phases.c_str(), output_s, renderer ? " and rendering" : "", stats_s,
                setup_s);
    if (renderer) std::printf("%s\n", renderer->finish().c_str());
    return kExitOk;
  } catch (const UnstableRun& e) {
    return fail(e.what() + kept, kExitUnstable);
  } catch (const std::exception& e) {
    return fail(e.what() + kept);
  } catch (...) {
    return fail("unknown error" + kept);
  }
}

int check_scene(const std::string& scene_path, const std::vector<std::string>& overrides,
                double resolution, std::ostream& out) {
  try {
    const Scene s = load_scene(scene_path, overrides, resolution);
    std::unique_ptr<Simulation> sim = make_simulation(s);
    out << "scene      " << scene_path << " (\"" << s.name << "\", " << s.dim << "D)\n";
    if (!s.description.empty()) {
      std::istringstream lines(s.description);
      for (std::string line; std::getline(lines, line);) out << "           " << line << "\n";
    }
    out << "grid       dx " << s.dx << ", domain [" << s.domain_min.head(s.dim).transpose()
        << "] .. [" << s.domain_max.head(s.dim).transpose() << "], cells";
    for (int d = 0; d < s.dim; ++d)
      out << (d ? " x " : " ") << std::lround((s.domain_max[d] - s.domain_min[d]) / s.dx);
    out << "\n";
    for (const MaterialSpec& m : s.materials) {
      const MaterialParams& p = m.params;
      out << "material   " << m.name << ": " << model_name(p.model) << ", E " << p.E << ", nu "
          << p.nu << ", rho " << p.rho << " -> mu " << p.mu << ", lambda " << p.lambda;
      if (p.kx != 0 || p.ky != 0) {
        out << ", kx " << p.kx;
        if (s.dim == 3) out << ", ky " << p.ky;
      }
      out << ", wave speed " << wave_speed(p) << (m.damage.enabled ? ", damage" : "");
      const PlasticParams& y = m.plasticity;
      if (y.surface == YieldSurface::VonMises)
        out << ", von Mises plasticity (yield stress " << y.yield_stress << ", hardening "
            << y.hardening << ")";
      if (y.surface == YieldSurface::DruckerPrager)
        out << ", Drucker-Prager plasticity (friction " << y.friction << ", cohesion term "
            << y.cohesion_term << (y.volume_correction ? ", volume correction" : "") << ")";
      if (m.inextensibility.enabled) {
        out << ", inextensible fibers";
        if (m.inextensibility.relaxation > 0)
          out << " (relaxed: a fiber of " << m.inextensibility.relaxation << " Pa)";
      }
      out << "\n";
      if (m.damage.enabled) print_crack_onset(out, s, m);
    }
    if (s.integrator == Integrator::Implicit) {
      const NewtonSettings& n = s.newton;
      out << "integrator implicit (backward Euler): Newton to " << n.tolerance
          << " dx/dt, at most " << n.max_iterations << " a step; CG to " << n.cg_tolerance
          << ", preconditioner ";
      if (s.implicit_preconditioner == ImplicitPreconditioner::Auto)
        out << "auto (Jacobi; multigrid once a solve passes " << n.cg_escalate_after
            << " iterations)\n";
      else
        out << (s.implicit_preconditioner == ImplicitPreconditioner::Multigrid ? "multigrid"
                                                                               : "Jacobi")
            << "\n";
    } else {
      out << "integrator explicit (symplectic Euler)\n";
    }
    if (std::any_of(s.materials.begin(), s.materials.end(),
                    [](const MaterialSpec& m) { return m.inextensibility.enabled; }))
      out << "inextens.  projection after each grid update: CG to " << s.inextensibility.tolerance
          << ", "
          << (s.inextensibility.preconditioner == InextensibilityPreconditioner::Cholesky
                  ? "Cholesky"
                  : "Jacobi")
          << " preconditioner\n";
    if (s.damage.solver != DamageSolver::None) {
      out << "cracking   "
          << (s.damage.solver == DamageSolver::Explicit ? "explicit" : "implicit")
          << " damage solver, l0 " << s.damage.l0 << ", ";
      if (s.damage.split_fields)
        out << "crack fields (a node splits at damage " << s.damage.split_damage << ")\n";
      else
        out << "one velocity field (the paper's; damage.split_fields for crack fields)\n";
      // The paper's method is the default on purpose (docs/materials.md); say what it does
      // to fibered materials where the recipe for sharp cracks could be used instead.
      const bool fibered = std::any_of(
          s.materials.begin(), s.materials.end(), [](const MaterialSpec& m) {
            return m.damage.enabled && (m.damage.alpha[0] != 0 || m.damage.alpha[1] != 0) &&
                   !m.damage.anisotropic_surface();
          });
      const bool inextensible =
          std::any_of(s.materials.begin(), s.materials.end(),
                      [](const MaterialSpec& m) { return m.inextensibility.enabled; });
      if (fibered && !s.damage.split_fields && s.integrator == Integrator::Explicit &&
          !inextensible)
        out << "           (paper's method: where crack faces slide, bands widen to 7-8 particle "
               "spacings and cracks may cross the fibers; for sharp cracks along them see "
               "docs/materials.md, \"Cracks that follow the fibers and stay sharp\")\n";
    }
    const nlohmann::json& objects = s.resolved.at("objects");
    for (size_t i = 0; i < s.objects.size(); ++i) {
      const ObjectSpec& ob = s.objects[i];
      out << "object     " << i << ": " << objects.at(i).at("shape").at("type").get<std::string>()
          << ", material " << s.materials[size_t(ob.material)].name;
      if (ob.kind != ObjectKind::Volume) {
        const bool surface = ob.kind == ObjectKind::Surface;
        out << ", " << (surface ? "surface" : "curves") << " of " << ob.mesh->vertices.size()
            << " vertices and " << ob.mesh->elements.size()
            << (surface ? " triangles, thickness " : " segments, radius ")
            << (surface ? ob.thickness : ob.radius) << "\n";
        continue;
      }
      if (ob.fem) {
        const std::vector<MeshFigures> meshes = sim->body_meshes();
        const MeshFigures& f = meshes.at(i);
        out << ", FEM mesh of " << f.nodes << " nodes, " << f.elements
            << (s.dim == 2 ? " triangles" : " tetrahedra");
        if (ob.fem_mesh)
          out << " (read from its file, mean edge " << f.mean_edge << ")";
        else
          out << " (mesh_size " << ob.mesh_size << ", mean edge " << f.mean_edge << ")";
        out << ", worst quality " << f.worst_quality
            << " (element " << f.worst_element << "), smallest height " << f.smallest_height
            << "\n";
        continue;
      }
      for (const RegionSpec& r : ob.regions)
        out << " (" << s.materials[size_t(r.material)].name << " in a "
            << objects.at(i).at("regions").at(&r - ob.regions.data()).at("shape").at("type").get<std::string>()
            << ")";
      out << ", " << ob.ppc << " particles per cell" << (ob.grid_sampling ? " (lattice)" : "")
          << "\n";
    }
    out << "boundaries walls " << s.resolved.at("grid").at("walls").get<std::string>() << ", "
        << s.boundaries.size() << " collider(s)";
    const nlohmann::json& colliders = s.resolved.at("boundaries");
    for (size_t i = 0; i < colliders.size(); ++i)
      out << (i ? ", " : ": ") << colliders[i].at("type").get<std::string>() << " "
          << colliders[i].at("shape").at("type").get<std::string>();
    out << "\n";
    const DtLimits limits = sim->dt_limits();
    const double dt = limits.dt();
    size_t frame_bytes = 0;
    std::string encoded;
    for (const std::string& f : s.formats)
      encode_points(sim->frame_rows(), f, &encoded), frame_bytes += encoded.size();
    for (const MeshPart& part : sim->frame_meshes())
      for (const std::string& f : mesh_part_formats_of(part, s.mesh_formats))
        frame_bytes += encode_mesh_part(part, f).size();
    const size_t checkpoint = sim->checkpoint().size();
    const size_t checkpoint_max = sim->checkpoint_bytes_max();
    // Frame 0, every output_every-th frame, and the last frame.
    const int written = 1 + s.frames / s.output_every + (s.frames % s.output_every != 0 ? 1 : 0);
    if (!s.objects.empty() && s.objects[0].fem)
      out << "nodes      " << sim->num_particles() << " (FEM: frames list the nodes)\n";
    else
      out << "particles  " << sim->num_particles() << "\n";
    out << "time       " << s.frames << " frames of " << s.frame_dt << " s; dt " << dt
        << " s at rest (about " << std::lround(std::ceil(s.frame_dt / dt))
        << " steps per frame), set by " << limits.limiting() << "\n";
    out << "dt limits  max_dt " << limits.max_dt << ", wave speed " << limits.wave;
    if (std::isfinite(limits.velocity)) out << ", particle speed " << limits.velocity;
    if (std::isfinite(limits.damage))
      out << ", explicit damage " << limits.damage << " (" << limits.damage_cracking
          << " while cracks grow)";
    out << "\n";
    out << "memory     about " << size_text(double(sim->memory_bytes())) << "\n";
    out << "output     " << written << " frames of " << size_text(double(frame_bytes)) << " ("
        << size_text(double(frame_bytes) * written) << "), checkpoint "
        << size_text(double(checkpoint));
    // Fields that hold one value for every particle are written once: later checkpoints grow
    // as the values part.
    if (checkpoint_max > checkpoint) out << " now, up to " << size_text(double(checkpoint_max));
    out << "\n";
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  } catch (...) {
    return fail("unknown error");
  }
}

void print_info(std::ostream& out) {
  out << "tear " << TEAR_VERSION << "\n";
#ifdef TEAR_FLOAT
  out << "precision   float\n";
#else
  out << "precision   double\n";
#endif
#ifdef TEAR_ENABLE_ASSERTS
  out << "asserts     on\n";
#else
  out << "asserts     off\n";
#endif
  out << "compiler    " << __VERSION__ << "\n";
  // The vector instructions Eigen was compiled for (128-bit in every build: CMakeLists.txt,
  // TEAR_NATIVE) and those of the transfers' lanes (math/lanes.h): AVX in native builds on
  // machines that have it.
  out << "simd        Eigen " << Eigen::SimdInstructionSetsInUse() << "; transfers "
#if defined(__AVX__) || defined(TEAR_LANES_AVX)
      << "AVX"
#else
      << "SSE2"
#endif
#ifdef TEAR_NATIVE_BUILD
      << " (this machine's: TEAR_NATIVE)\n";
#else
      << " (portable: TEAR_NATIVE off)\n";
#endif
  out << "lto         "
#ifdef TEAR_LTO_BUILD
      << "on (TEAR_LTO)\n";
#else
      << "off\n";
#endif
  out << "eigen       " << EIGEN_WORLD_VERSION << "." << EIGEN_MAJOR_VERSION << "."
      << EIGEN_MINOR_VERSION << "\n";
  out << "onetbb      " << threading_library_version() << "\n";
  out << "threads     " << available_threads() << " available\n";
  out << "embree      " << embree_version() << "\n";
  out << "libpng      " << libpng_version() << "\n";
  // The mesher's OpenVDB module is loaded here (tear mesh and surface renders load it too).
  std::string openvdb;
  try {
    openvdb = openvdb_version();
  } catch (const std::exception& e) {
    openvdb = std::string("not loaded: ") + e.what();
  }
  out << "openvdb     " << openvdb << "\n";
  const std::string ffmpeg = ffmpeg_path();
  out << "ffmpeg      " << (ffmpeg.empty() ? "not found on PATH (no preview.mp4)" : ffmpeg) << "\n";
}

}  // namespace tear
