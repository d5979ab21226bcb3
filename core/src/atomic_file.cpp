#include "millnet/core/atomic_file.hpp"

#include "millnet/core/error.hpp"
#include "millnet/core/interrupt.hpp"
#include "millnet/core/output_set.hpp"

#include <cerrno>
#include <charconv>
#include <system_error>
#include <unistd.h>

namespace millnet {
namespace fs = std::filesystem;

namespace {
fs::path temp_name(const fs::path& path) {
  fs::path tmp = path;
  tmp += ".tmp-" + std::to_string(static_cast<long>(::getpid()));
  return tmp;
}
/// "write failed", with the reason when it is one a user can act on: a full disk and a file-size
/// limit (`ulimit -f`: SIGXFSZ is ignored, interrupt.hpp) read alike (issue 42 §9).
std::string write_failure(int err) {
  switch (err) {
    case ENOSPC: return "write failed: no space left on device";
    case EDQUOT: return "write failed: disk quota exceeded";
    case EFBIG: return "write failed: the file would exceed the file-size limit (ulimit -f)";
    case EIO: return "write failed: input/output error";
    default: return "write failed";
  }
}
void ensure_parent(const fs::path& path) {
  if (path.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw file_error(path.parent_path().string(), "cannot create folder: " + ec.message());
  }
}
}  // namespace

AtomicOFStream::AtomicOFStream(fs::path path, bool binary) : path_(std::move(path)), tmp_(temp_name(path_)) {
  ensure_parent(path_);
  slot_ = register_temp_file(tmp_);  // before the file exists: an interrupt from here on removes it
  out_.open(tmp_, binary ? std::ios::out | std::ios::binary | std::ios::trunc : std::ios::out | std::ios::trunc);
  if (!out_) {
    unregister_temp_file(slot_);
    throw file_error(path_.string(), "cannot open for writing");
  }
}

AtomicOFStream::~AtomicOFStream() {
  if (!committed_) {
    out_.close();
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
  unregister_temp_file(slot_);
}

void AtomicOFStream::commit() {
  out_.flush();
  const int flush_errno = errno;
  const bool ok = static_cast<bool>(out_);
  out_.close();
  // The destructor removes the temporary. The stream keeps the failed write's errno in errno (nothing
  // runs after a failed write but the no-ops of a failed stream).
  if (!ok || !out_) throw file_error(path_.string(), write_failure(ok ? errno : flush_errno));
  if (OutputSet::stage(tmp_, path_)) {  // an open set renames it with the command's other outputs
    committed_ = true;
    // The temporary stays registered for an interrupt until the set renames or removes it; its
    // slot is reclaimed once the file is gone (interrupt.cpp).
    slot_ = -1;
    return;
  }
  std::error_code ec;
  fs::rename(tmp_, path_, ec);
  if (ec) throw file_error(path_.string(), "cannot rename temporary file into place: " + ec.message());
  committed_ = true;
  unregister_temp_file(slot_);
  slot_ = -1;
}

void write_file_atomic(const fs::path& path, std::string_view content) {
  AtomicOFStream out(path, true);
  out.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  out.commit();
}

void write_file_atomic(const fs::path& path, const std::vector<unsigned char>& bytes) {
  write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::string read_file(const fs::path& requested) {
  // A file this command wrote into its still open OutputSet is read from its temporary.
  const fs::path path = OutputSet::pending(requested).value_or(requested);
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(path.string(), "no such file");
  if (fs::is_directory(path, ec)) throw file_error(path.string(), "is a folder, expected a file");
  // Before opening: a FIFO blocks the open, /dev/zero (behind a symlink named x.stl) never ends
  // (tests/corpus/cli: not_a_regular_file_*).
  if (!fs::is_regular_file(path, ec))
    throw file_error(path.string(), "not a regular file (a device, FIFO or socket), expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path.string(), "cannot open for reading");
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw file_error(path.string(), "read failed");
  return s;
}

std::string format_double(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace millnet
