#pragma once
// Outputs are never left half-written: everything goes to "<path>.tmp-<pid>" in the same folder
// and is renamed over <path> only when complete (rename is atomic on POSIX within a file system).
// While it is open, the temporary file is registered for removal on SIGINT/SIGTERM (interrupt.hpp).
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace millnet {

/// Writes `content` to `path` atomically; creates parent folders. Throws millnet::Error.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);
void write_file_atomic(const std::filesystem::path& path, const std::vector<unsigned char>& bytes);

/// Reads a whole regular file; throws millnet::Error naming the path when it is missing, a folder,
/// not a regular file (device, FIFO, socket) or cannot be read.
[[nodiscard]] std::string read_file(const std::filesystem::path& path);

/// A stream to a temporary file that becomes `path` on commit(); removed if never committed.
class AtomicOFStream {
public:
  explicit AtomicOFStream(std::filesystem::path path, bool binary = false);
  AtomicOFStream(const AtomicOFStream&) = delete;
  AtomicOFStream& operator=(const AtomicOFStream&) = delete;
  ~AtomicOFStream();
  std::ofstream& stream() { return out_; }
  template <class T>
  AtomicOFStream& operator<<(const T& v) {
    out_ << v;
    return *this;
  }
  void commit();  ///< flush, close, rename; throws millnet::Error on I/O failure

private:
  std::filesystem::path path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  ///< the temporary file's entry in the interrupt table (interrupt.hpp)
};

/// Shortest decimal text that reads back to the same double (round trip bit for bit), "%.17g"-free.
[[nodiscard]] std::string format_double(double v);

}  // namespace millnet
