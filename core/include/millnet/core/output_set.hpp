#pragma once
// A command's outputs are committed together or not at all (issue 15: `train` that failed on its
// chart left a loadable model.json, `sample` an all-zero grid.csv when its picture failed).
//
// While an OutputSet is open, every atomic write (write_file_atomic, AtomicOFStream::commit) stops
// at its temporary "<path>.tmp-<pid>" and is staged here instead of being renamed into place.
// commit() renames them all at the end; a set that is destroyed uncommitted (an exception on the way
// out) removes its temporaries, so a failed command leaves no output behind. Sets nest: an inner set
// (one part of a batch) hands its files to the enclosing set on commit, or drops them on failure, so
// a batch commits each good part completely and leaves nothing of a bad one.
//
// read_file() of a staged path reads its temporary, so a command may read back what it wrote.
#include <filesystem>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

namespace millnet {

class OutputSet {
public:
  OutputSet();  ///< becomes the open set (the innermost, when one is open already)
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  ///< uncommitted: removes the staged temporaries

  /// Renames every staged file into place (the outermost set) or hands them to the enclosing set.
  /// SIGINT and SIGTERM are held back during the renames (DeferInterrupts): all or nothing.
  /// Throws millnet::Error naming the file when a rename fails; the files this call had already put
  /// in place are removed again.
  void commit();

  /// Called by the atomic writers: `tmp` (complete, closed) becomes `path` when the set commits.
  /// False when no set is open (the caller renames at once). Throws millnet::Error when `path` is a
  /// folder (caught here, before any file of the set is in place).
  static bool stage(const std::filesystem::path& tmp, const std::filesystem::path& path);

  /// The temporary staged for `path` in an open set, if any.
  [[nodiscard]] static std::optional<std::filesystem::path> pending(const std::filesystem::path& path);

private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> files_;  ///< (tmp, path)
  OutputSet* outer_ = nullptr;
  bool done_ = false;
};

}  // namespace millnet
