#pragma once
// Progress on long work: one self-overwriting line on stderr, only when stderr is a terminal and
// the user did not ask for --quiet. Call tick() from serial code only (never inside an OpenMP
// region: ARCHITECTURE.md's OpenMP rules); parallel loops report per finished block.
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>

namespace millnet {

/// Callback modules accept for progress: (done, total). Empty = no reporting.
using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

class Progress {
public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  void tick(std::size_t n = 1);
  void set(std::size_t done);
  void finish();
  [[nodiscard]] ProgressFn callback();

  /// Global switch set by the CLI (--quiet) ; progress is also off when stderr is not a tty.
  static void set_quiet(bool quiet);
  [[nodiscard]] static bool enabled();

private:
  void draw(bool force);
  std::string label_;
  std::size_t total_, done_ = 0;
  std::chrono::steady_clock::time_point last_;
  bool finished_ = false;
};

}  // namespace millnet
