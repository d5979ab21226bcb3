// A reader in a child process (see cad_isolate.hpp).
#include "cad_isolate.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#if defined(__SANITIZE_ADDRESS__)
#define MILLNET_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MILLNET_UNDER_ASAN 1
#endif
#endif

namespace millnet::ingest::detail {

namespace {

/// Fields of /proc/<pid>/statm in bytes: 0 = total program size, 1 = resident set.
double statm_bytes(pid_t pid, int field) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%d/statm", static_cast<int>(pid));
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  char buf[256];
  const ssize_t n = ::read(fd, buf, sizeof buf - 1);
  ::close(fd);
  if (n <= 0) return 0;
  buf[n] = 0;
  unsigned long long v[2] = {0, 0};
  if (std::sscanf(buf, "%llu %llu", &v[0], &v[1]) != 2) return 0;
  return static_cast<double>(v[field]) * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

void write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::write(fd, p, n);
    if (k < 0) {
      if (errno == EINTR) continue;
      ::_exit(4);  // the parent is gone or stopped reading
    }
    p += k;
    n -= static_cast<std::size_t>(k);
  }
}

/// The child's side of cad_isolate.hpp's contract, before the work.
void child_setup(const ChildLimits& limits, double size_at_fork) {
  // The parent's handlers are not the child's: its temporary files (interrupt.hpp) are not the
  // child's to remove, and a sanitizer's report of a crash would go to /dev/null — the parent names
  // the signal instead.
  for (const int sig : {SIGINT, SIGTERM, SIGPIPE, SIGXCPU, SIGXFSZ, SIGHUP, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
    ::signal(sig, SIG_DFL);
  const int null = ::open("/dev/null", O_RDWR);
  if (null >= 0) {
    ::dup2(null, 0);
    ::dup2(null, 1);
    ::dup2(null, 2);
    if (null > 2) ::close(null);
  }
  rlimit none{0, 0};
  ::setrlimit(RLIMIT_CORE, &none);
  ::setrlimit(RLIMIT_FSIZE, &none);
  rlimit cpu{};
  if (::getrlimit(RLIMIT_CPU, &cpu) == 0) {
    const auto secs = static_cast<rlim_t>(std::ceil(std::max(1.0, std::min(limits.wall_seconds, 1e9))));
    if (cpu.rlim_max == RLIM_INFINITY || secs + 2 <= cpu.rlim_max) {
      cpu.rlim_cur = secs;
      cpu.rlim_max = secs + 2;  // SIGXCPU at the soft limit, SIGKILL two seconds later
      ::setrlimit(RLIMIT_CPU, &cpu);
    }
  }
#if !defined(MILLNET_UNDER_ASAN)
  rlimit as{};
  const double want = size_at_fork + limits.memory_bytes + 256.0 * 1024 * 1024;
  if (size_at_fork > 0 && want < 1.8e19 && ::getrlimit(RLIMIT_AS, &as) == 0) {
    const auto w = static_cast<rlim_t>(want);
    if (as.rlim_cur == RLIM_INFINITY || w < as.rlim_cur) {
      as.rlim_cur = w;
      ::setrlimit(RLIMIT_AS, &as);
    }
  }
#else
  (void)size_at_fork;
#endif
}

/// Kills and reaps the child if the parent leaves early (an exception while reading its answer).
struct Reaper {
  pid_t pid;
  bool reaped = false;
  ~Reaper() {
    if (reaped) return;
    ::kill(pid, SIGKILL);
    int st = 0;
    while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
  }
};

}  // namespace

std::string signal_name(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV, segmentation fault";
    case SIGBUS: return "SIGBUS, bus error";
    case SIGABRT: return "SIGABRT, abort";
    case SIGFPE: return "SIGFPE, arithmetic exception";
    case SIGILL: return "SIGILL, illegal instruction";
    case SIGKILL: return "SIGKILL";
    case SIGXCPU: return "SIGXCPU, CPU time limit";
    case SIGXFSZ: return "SIGXFSZ, file size limit";
    case SIGTERM: return "SIGTERM";
    case SIGINT: return "SIGINT";
    default: return "signal " + std::to_string(sig);
  }
}

ChildOutcome run_in_child(const std::function<void(const std::function<void(const std::string&)>& send)>& work,
                          const ChildLimits& limits) {
  ChildOutcome out;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    out.end = ChildOutcome::End::NoFork;
    out.status = errno;
    return out;
  }
  const double size_at_fork = statm_bytes(::getpid(), 0), resident_at_fork = statm_bytes(::getpid(), 1);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) {
    out.end = ChildOutcome::End::NoFork;
    out.status = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    return out;
  }
  if (pid == 0) {
    ::close(fds[0]);
    child_setup(limits, size_at_fork);
    const int fd = fds[1];
    int code = 0;
    try {
      work([fd](const std::string& s) { write_all(fd, s.data(), s.size()); });
    } catch (...) {
      code = 3;
    }
    ::_exit(code);
  }
  ::close(fds[1]);
  Reaper reaper{pid};
  enum class Kill { None, Time, Memory } killed = Kill::None;
  const auto deadline = t0 + std::chrono::duration<double>(std::min(limits.wall_seconds, 1e9));
  const double memory_cap = resident_at_fork + limits.memory_bytes;
  char chunk[1 << 16];
  for (bool open = true; open;) {  // O(answer bytes + run time / 20 ms)
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      killed = Kill::Time;
      break;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count();
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::clamp<long long>(left, 1, 20)));
    if (r < 0 && errno != EINTR) break;
    if (r > 0) {
      const ssize_t k = ::read(fds[0], chunk, sizeof chunk);
      if (k > 0)
        out.answer.append(chunk, static_cast<std::size_t>(k));
      else if (k == 0 || (errno != EINTR && errno != EAGAIN))
        open = false;
    }
    if (open && statm_bytes(pid, 1) > memory_cap) {
      killed = Kill::Memory;
      break;
    }
  }
  ::close(fds[0]);
  if (killed != Kill::None) ::kill(pid, SIGKILL);
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  reaper.reaped = true;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (killed == Kill::Time) {
    out.end = ChildOutcome::End::TimedOut;
  } else if (killed == Kill::Memory) {
    out.end = ChildOutcome::End::OutOfMemory;
  } else if (WIFSIGNALED(st)) {
    out.signal = WTERMSIG(st);
    out.end = out.signal == SIGXCPU ? ChildOutcome::End::TimedOut : ChildOutcome::End::Signal;
  } else {
    out.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    out.end = out.status == 0 && !out.answer.empty() ? ChildOutcome::End::Answered : ChildOutcome::End::Exited;
  }
  return out;
}

}  // namespace millnet::ingest::detail
