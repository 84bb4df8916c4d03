// exec/: wall-clock time per phase of a step. A PhaseTimer adds the time from its construction
// to its destruction to a counter, so a step reads as a list of scoped phases.
#pragma once

#include <chrono>

namespace tear {

class PhaseTimer {
 public:
  explicit PhaseTimer(double* seconds) : seconds_(seconds), start_(Clock::now()) {}
  ~PhaseTimer() { *seconds_ += std::chrono::duration<double>(Clock::now() - start_).count(); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  double* seconds_;
  Clock::time_point start_;
};

// Seconds since `start` on the same clock (run totals, progress lines).
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tear
