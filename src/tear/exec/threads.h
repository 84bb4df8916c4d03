// exec/: the thread count. A ThreadLimit caps the threads every parallel loop may use while it
// lives (tear run --threads, benchmarks); nothing else in tear names the threading library.
#pragma once

#include <memory>
#include <string>

namespace tear {

class ThreadLimit {
 public:
  // threads <= 0: no cap (all hardware threads).
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Threads a parallel loop can use by default on this machine.
int available_threads();
// Threads a parallel loop can use now: available_threads() or the cap of a ThreadLimit alive.
int allowed_threads();
// The version of oneTBB, the threading library behind exec/ ("2021.8"; tear info).
std::string threading_library_version();

}  // namespace tear
