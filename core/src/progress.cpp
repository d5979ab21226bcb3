#include "millnet/core/progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace millnet {
namespace {
bool g_quiet = false;
}

void Progress::set_quiet(bool quiet) { g_quiet = quiet; }
bool Progress::enabled() { return !g_quiet && ::isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), last_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::tick(std::size_t n) { set(done_ + n); }

void Progress::set(std::size_t done) {
  done_ = done;
  draw(false);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled()) return;
  std::fprintf(stderr, "\r%s: %zu/%zu done\x1b[K\n", label_.c_str(), done_, total_);
}

ProgressFn Progress::callback() {
  return [this](std::size_t done, std::size_t total) {
    total_ = total;
    set(done);
  };
}

void Progress::draw(bool force) {
  if (!enabled()) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_ < std::chrono::milliseconds(100) && done_ < total_) return;
  last_ = now;
  const double pct = total_ ? 100.0 * static_cast<double>(done_) / static_cast<double>(total_) : 100.0;
  std::fprintf(stderr, "\r%s: %zu/%zu (%.0f%%)\x1b[K", label_.c_str(), done_, total_, pct);
  std::fflush(stderr);
}

}  // namespace millnet
