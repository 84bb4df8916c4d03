#include "tear/render/video.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace tear {

namespace fs = std::filesystem;

namespace {

// A folder beside the video that is removed with everything in it, whatever happens.
struct TempDir {
  fs::path path;
  explicit TempDir(const fs::path& near) {
    std::string pattern = (near / ".tear-video-XXXXXX").string();
    if (!::mkdtemp(pattern.data()))
      throw std::runtime_error(near.string() +
                               ": cannot create a temporary folder: " + std::strerror(errno));
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last.empty() ? "no message" : last;
}

}  // namespace

std::string ffmpeg_path() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "ffmpeg";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

bool make_video(const std::vector<std::string>& frames, double fps, const std::string& out,
                int threads) {
  if (frames.empty()) throw std::runtime_error(out + ": no frames to encode");
  fs::path parent = fs::path(out).parent_path();
  if (parent.empty()) parent = ".";
  TempDir tmp(parent);
  // ffmpeg's image sequence input wants consecutive numbers; frames may have gaps.
  for (size_t i = 0; i < frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", i);
    std::error_code ec;
    fs::create_symlink(fs::absolute(frames[i]), tmp.path / name, ec);
    if (ec) throw std::runtime_error(out + ": cannot link " + frames[i] + ": " + ec.message());
  }
  char rate[32];
  std::snprintf(rate, sizeof(rate), "%.6g", fps);
  const std::string video = (tmp.path / "video.mp4").string();
  const std::string log = (tmp.path / "ffmpeg.log").string();
  const std::string input = (tmp.path / "%06d.png").string();
  std::vector<std::string> args = {"ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-y",
                                   "-framerate", rate, "-i", input,
                                   // yuv420p needs even sizes.
                                   "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
                                   "-pix_fmt", "yuv420p", "-crf", "20", "-movflags", "+faststart"};
  if (threads > 0) args.insert(args.end(), {"-threads", std::to_string(threads)});
  args.push_back(video);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int err = posix_spawnp(&pid, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err == ENOENT) return false;
  if (err != 0) throw std::runtime_error(out + ": cannot start ffmpeg: " + std::strerror(err));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR)
      throw std::runtime_error(out + ": waiting for ffmpeg: " + std::strerror(errno));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFEXITED(status)
                                ? "exit code " + std::to_string(WEXITSTATUS(status))
                                : "killed by signal " + std::to_string(WTERMSIG(status));
    throw std::runtime_error(out + ": ffmpeg failed (" + how + "): " + last_line(log));
  }
  std::error_code ec;
  fs::rename(video, out, ec);
  if (ec) throw std::runtime_error(out + ": cannot write: " + ec.message());
  return true;
}

}  // namespace tear
