#include "millnet/core/output_set.hpp"

#include "millnet/core/error.hpp"
#include "millnet/core/interrupt.hpp"

#include <system_error>

namespace millnet {
namespace fs = std::filesystem;

namespace {
// One open set per process (OpenMP threads of a command write into it too), guarded by one mutex.
std::mutex g_mutex;
OutputSet* g_open = nullptr;

fs::path key(const fs::path& p) { return fs::absolute(p).lexically_normal(); }
}  // namespace

OutputSet::OutputSet() {
  std::lock_guard<std::mutex> lock(g_mutex);
  outer_ = g_open;
  g_open = this;
}

OutputSet::~OutputSet() {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_open == this) g_open = outer_;
  if (done_) return;
  for (const auto& [tmp, path] : files_) {
    std::error_code ec;
    fs::remove(tmp, ec);
  }
}

bool OutputSet::stage(const fs::path& tmp, const fs::path& path) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (!g_open) return false;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    fs::remove(tmp, ec);
    throw file_error(path.string(), "is a folder, expected a file to write");
  }
  const fs::path k = key(path);
  for (auto& f : g_open->files_)
    if (key(f.second) == k) {  // written twice: the later content wins (same temporary name)
      if (f.first != tmp) fs::remove(f.first, ec);
      f.first = tmp;
      return true;
    }
  g_open->files_.emplace_back(tmp, path);
  return true;
}

std::optional<fs::path> OutputSet::pending(const fs::path& path) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (!g_open) return std::nullopt;
  const fs::path k = key(path);
  for (const OutputSet* s = g_open; s; s = s->outer_)
    for (const auto& f : s->files_)
      if (key(f.second) == k) return f.first;
  return std::nullopt;
}

void OutputSet::commit() {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (done_) return;
  if (outer_) {
    for (auto& f : files_) {
      bool merged = false;
      for (auto& o : outer_->files_)
        if (key(o.second) == key(f.second)) {
          o.first = f.first;
          merged = true;
        }
      if (!merged) outer_->files_.push_back(f);
    }
    done_ = true;
    return;
  }
  // SIGINT/SIGTERM wait until every file is in place (or every one removed again): a signal between
  // two renames left part of the set (issue 42 §9; tests/core/test_output_set.cpp).
  const DeferInterrupts hold;
  std::size_t n = 0;
  for (; n < files_.size(); ++n) {
    std::error_code ec;
    fs::rename(files_[n].first, files_[n].second, ec);
    if (ec) {
      const fs::path failed = files_[n].second;
      const std::string why = ec.message();
      for (std::size_t i = 0; i < n; ++i) fs::remove(files_[i].second, ec);  // all or nothing
      for (std::size_t i = n; i < files_.size(); ++i) fs::remove(files_[i].first, ec);
      done_ = true;
      throw file_error(failed.string(), "cannot rename temporary file into place: " + why);
    }
  }
  done_ = true;
}

}  // namespace millnet
