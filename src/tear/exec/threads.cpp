#include "tear/exec/threads.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/version.h>

#include <algorithm>

namespace tear {

struct ThreadLimit::Impl {
  explicit Impl(int threads)
      : control(tbb::global_control::max_allowed_parallelism, size_t(threads)) {}
  tbb::global_control control;
};

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0) impl_ = std::make_unique<Impl>(threads);
}

ThreadLimit::~ThreadLimit() = default;

int available_threads() { return tbb::info::default_concurrency(); }

int allowed_threads() {
  return int(
      std::min(size_t(available_threads()),
               tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
}

std::string threading_library_version() {
  return std::to_string(TBB_VERSION_MAJOR) + "." + std::to_string(TBB_VERSION_MINOR);
}

}  // namespace tear
