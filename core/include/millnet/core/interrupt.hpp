#pragma once
// Ctrl-C leaves no half-written file (issue 12 §1). AtomicOFStream registers its temporary file
// here while it is open; on the first registration, SIGINT and SIGTERM handlers are installed that
// unlink every registered temporary file (async-signal-safe: unlink only, over a fixed table) and
// then re-raise the signal with its default action, so the process still ends "by the signal"
// (exit status 128 + n in a shell). Outputs already renamed into place are complete files and stay.
//
// SIGXFSZ (a file-size limit, `ulimit -f`) is ignored from the first registration on, so that the
// write fails with EFBIG and is reported like a full disk instead of ending the process with its
// temporaries left behind (issue 42 §9).
#include <filesystem>

namespace millnet {

/// Registers `tmp` to be removed if the process is interrupted; returns a slot for
/// unregister_temp_file, or −1 when the table (1024 slots) is full or the path too long (the file is
/// then simply not removed on a signal). Installs the signal handlers once.
[[nodiscard]] int register_temp_file(const std::filesystem::path& tmp);

/// Forgets a slot (after the file was renamed into place or removed); −1 is ignored.
void unregister_temp_file(int slot);

/// While one is alive, SIGINT and SIGTERM (delivered to any thread) are held back: the handler notes
/// the signal and returns, and the destructor of the outermost one acts on it (removes the
/// registered temporaries, ends the process by the signal). OutputSet::commit holds one around its
/// renames, so that a signal leaves all of an output set in place or none of it (issue 42 §9).
class DeferInterrupts {
public:
  DeferInterrupts();
  DeferInterrupts(const DeferInterrupts&) = delete;
  DeferInterrupts& operator=(const DeferInterrupts&) = delete;
  ~DeferInterrupts();
};

}  // namespace millnet
