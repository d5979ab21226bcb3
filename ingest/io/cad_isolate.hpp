#pragma once
// Running a reader that may crash, hang or grow without bound in a child process (issue 42; private
// to millnet::ingest_io). fork() + _exit(): no executable to find, so it works inside the test
// executables and the fuzz targets as well as in `millnet`. The child:
//  * has its standard input, output and error on /dev/null (no library text reaches the user),
//    SIGINT/SIGTERM/SIGPIPE and the crash signals back to their default action (the parent's
//    handlers remove the parent's temporary files, a sanitizer's report would go to /dev/null:
//    the parent names the signal instead), no core dumps;
//  * RLIMIT_CPU = the time limit (SIGXCPU), RLIMIT_FSIZE = 0 (it writes no file: SIGXFSZ),
//    RLIMIT_AS = its size at the fork + the memory limit + 256 MiB of slack — except under
//    AddressSanitizer, whose shadow reservation (terabytes of address space) no such limit admits;
//    there, and everywhere as a second line, the parent watches the child's resident set
//    (/proc/<pid>/statm, every 20 ms) and kills it beyond its size at the fork + the memory limit;
//  * hands its answer back over a pipe, read by the parent while it runs (no size limit of a
//    pipe buffer), and ends with _exit (no atexit handlers, no flushing of the parent's buffers).
// The parent kills the child (SIGKILL) when the wall-clock limit passes. Under Open MPI, fork()
// of a rank is allowed on the shared-memory and TCP transports (the child touches no MPI state and
// ends with _exit); on InfiniBand's verbs it is not, and Open MPI warns.
#include <functional>
#include <string>

namespace millnet::ingest::detail {

struct ChildLimits {
  double wall_seconds = 600;    ///< killed after this long (also the CPU limit, in whole seconds)
  double memory_bytes = 8.6e9;  ///< beyond the size at the fork
};

struct ChildOutcome {
  enum class End {
    Answered,     ///< exited 0 after writing its answer
    Signal,       ///< ended by a signal it raised or received (a crash): `signal`
    TimedOut,     ///< killed by the parent or by SIGXCPU after the time limit
    OutOfMemory,  ///< killed by the parent beyond the memory limit
    Exited,       ///< exited without an answer, or with a status other than 0: `status`
    NoFork,       ///< fork() or pipe() failed: `status` holds errno
  };
  End end = End::Exited;
  int signal = 0;
  int status = 0;
  std::string answer;  ///< everything the child wrote
  double seconds = 0;  ///< wall-clock time, fork to end
};

/// Runs `work` in a child process under `limits`; `work` writes its answer with `send` (any number
/// of calls). Exceptions escaping `work` end the child with status 3. Thread-safe.
[[nodiscard]] ChildOutcome run_in_child(
    const std::function<void(const std::function<void(const std::string&)>& send)>& work, const ChildLimits& limits);

/// "SIGSEGV", "SIGBUS", … (or "signal N").
[[nodiscard]] std::string signal_name(int sig);

}  // namespace millnet::ingest::detail
