#include "mpi_cluster.hpp"

#include "cli.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/output_set.hpp"
#include "millnet/core/progress.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>
#include <unistd.h>
#include <vector>

#ifdef MILLNET_HAVE_MPI
#include <mpi.h>
#endif

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
int g_rank = 0, g_size = 1;
#ifdef MILLNET_HAVE_MPI
bool g_started = false;
#endif

// Tags, per distribution: a command may distribute several times in a row (dataset: the labels by
// simulation, then the table's rows), and a rank told "no more" goes on to the next distribution
// while rank 0 still serves the last one. Its "ready" for the next one must not be taken as a
// request in this one (that hung `mpirun -np 3 millnet dataset` with two parts to label), so each
// distribution has its own pair of tags: every rank calls distribute() in the same order.
bool g_failure_shared = false;  // a distribution ended in a failure every rank was told of
#ifdef MILLNET_HAVE_MPI
int g_generation = 0;  // distributions started by this rank
int tag_result() {
  return 2 + 2 * (g_generation % 16000);
}  // worker → rank 0: [int64 index][uint8 ok][bytes]; −1 = "ready"
int tag_work() { return 3 + 2 * (g_generation % 16000); }  // rank 0 → worker: int64 next index; −1 = "no more"
#endif

/// Results received but not yet delivered, shared by rank 0's worker and communication threads.
struct Board {
  std::mutex m;
  std::condition_variable cv;
  std::size_t next = 0, n = 0, completed = 0;
  bool stop = false;
  std::map<std::size_t, std::pair<bool, std::string>> done;
  /// The next unit to compute, or n when none is left (or the hand-out stopped).
  std::size_t take() {
    std::lock_guard lk(m);
    return stop || next >= n ? n : next++;
  }
  void put(std::size_t i, bool ok, std::string&& bytes, bool stop_on_error) {
    {
      std::lock_guard lk(m);
      done.emplace(i, std::pair{ok, std::move(bytes)});
      ++completed;
      if (!ok && stop_on_error) stop = true;
    }
    cv.notify_all();
  }
};

std::pair<bool, std::string> run_unit(const UnitWork& work, std::size_t i) {
  try {
    return {true, work(i)};
  } catch (const std::exception& e) {
    return {false, e.what()};
  } catch (...) {
    return {false, "unknown error"};
  }
}

#ifdef MILLNET_HAVE_MPI
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (const char* s = std::getenv(v); s && *s) return true;
  return false;
}

std::string header(std::int64_t index, bool ok) {
  std::string h(9, '\0');
  std::memcpy(h.data(), &index, 8);
  h[8] = ok ? 1 : 0;
  return h;
}

/// Rank 0's communication thread: answers every other rank until each has been told "no more".
void serve(Board& b, DistributeStats& stats, bool stop_on_error) {
  int active = g_size - 1;
  std::vector<char> buf;
  while (active > 0) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, tag_result(), MPI_COMM_WORLD, &flag, &st);
    if (!flag) {  // a sleeping poll: the rank's own worker thread keeps the core
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    int count = 0;
    MPI_Get_count(&st, MPI_BYTE, &count);
    buf.resize(static_cast<std::size_t>(std::max(count, 9)));
    MPI_Recv(buf.data(), count, MPI_BYTE, st.MPI_SOURCE, tag_result(), MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    stats.bytes_to_root += static_cast<std::uint64_t>(count);
    std::int64_t index = -1;
    std::memcpy(&index, buf.data(), 8);
    if (index >= 0) ++stats.remote_units;
    if (index >= 0)
      b.put(static_cast<std::size_t>(index), buf[8] != 0,
            std::string(buf.data() + 9, static_cast<std::size_t>(count) - 9), stop_on_error);
    const std::size_t t = b.take();
    const std::int64_t next = t < b.n ? static_cast<std::int64_t>(t) : -1;
    MPI_Send(&next, 8, MPI_BYTE, st.MPI_SOURCE, tag_work(), MPI_COMM_WORLD);
    stats.bytes_from_root += 8;
    if (next < 0) --active;
  }
}

/// A rank other than 0: asks for units until told there are none left.
void work_for_root(const UnitWork& work) {
  std::string msg = header(-1, true);
  for (;;) {
    if (msg.size() > static_cast<std::size_t>(INT32_MAX))
      msg = header(-1, false);  // unreachable for our payloads; never send a count MPI cannot hold
    MPI_Send(msg.data(), static_cast<int>(msg.size()), MPI_BYTE, 0, tag_result(), MPI_COMM_WORLD);
    std::int64_t next = -1;
    MPI_Recv(&next, 8, MPI_BYTE, 0, tag_work(), MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (next < 0) return;
    auto [ok, bytes] = run_unit(work, static_cast<std::size_t>(next));
    if (bytes.size() > static_cast<std::size_t>(INT32_MAX) - 16) {
      ok = false;
      bytes = "the unit's result is " + std::to_string(bytes.size()) + " bytes, over MPI's 2 GiB message limit";
    }
    msg = header(next, ok);
    msg += bytes;
  }
}
#endif
}  // namespace

void cluster_init(int& argc, char**& argv) {
#ifdef MILLNET_HAVE_MPI
  if (g_started || !launched_by_mpi()) return;
  int provided = 0;
  // Serialized: during a distribution only rank 0's communication thread calls MPI.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
  g_started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  if (provided < MPI_THREAD_SERIALIZED && g_size > 1) {
    if (g_rank == 0)
      std::cerr << "millnet: error: this MPI library gives no MPI_THREAD_SERIALIZED support, which rank 0's "
                   "communication thread needs\n";
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  std::atexit(cluster_finalize);
#else
  (void)argc;
  (void)argv;
#endif
}

void cluster_finalize() {
#ifdef MILLNET_HAVE_MPI
  if (!g_started) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
#endif
}

bool cluster_failure_shared() { return g_failure_shared; }

void cluster_abort(int code) {
#ifdef MILLNET_HAVE_MPI
  if (!g_started || g_size <= 1) return;
  std::cerr.flush();
  MPI_Abort(MPI_COMM_WORLD, code);
#else
  (void)code;
#endif
}

int cluster_rank() { return g_rank; }
int cluster_size() { return g_size; }

DistributeStats distribute(std::size_t n, const UnitWork& work, const UnitResult& on_result, bool stop_on_error,
                           const std::string& label) {
  DistributeStats stats;
#ifdef MILLNET_HAVE_MPI
  ++g_generation;
  if (g_size > 1 && g_rank != 0) {
    work_for_root(work);
    // Rank 0 says whether the distribution failed: a rank must not go on to the command's next
    // distribution (or finish as if it succeeded) when rank 0 has stopped.
    char failed = 0;
    MPI_Bcast(&failed, 1, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (failed) {
      g_failure_shared = true;
      throw Error("the run stopped on rank 0");  // rank 0 prints the reason; this rank says nothing
    }
    return stats;
  }
#endif
  stats.units = n;
  Board b;
  b.n = n;
  Progress progress(label, n);
  std::thread comm;
#ifdef MILLNET_HAVE_MPI
  if (g_size > 1) comm = std::thread([&] { serve(b, stats, stop_on_error); });
#endif
  std::exception_ptr failure;
  bool halted = false;  // a failed unit delivered with stop_on_error, or on_result threw
  std::size_t delivered = 0;
  // Delivers the complete prefix; true when the distribution must stop.
  auto deliver = [&]() {
    for (;;) {
      std::pair<bool, std::string> r;
      {
        std::lock_guard lk(b.m);
        auto it = b.done.find(delivered);
        if (it == b.done.end()) return false;
        r = std::move(it->second);
        b.done.erase(it);
      }
      const std::size_t i = delivered++;
      try {
        on_result(i, r.first, std::move(r.second));
      } catch (...) {
        failure = std::current_exception();
        return true;
      }
      if (!r.first && stop_on_error) return true;
    }
  };
  auto halt = [&] {
    halted = true;
    std::lock_guard lk(b.m);
    b.stop = true;
  };
  for (;;) {
    if (deliver()) {
      halt();
      break;
    }
    {
      std::lock_guard lk(b.m);
      progress.set(b.completed);
    }
    const std::size_t i = b.take();
    if (i >= n) break;
    auto [ok, bytes] = run_unit(work, i);
    b.put(i, ok, std::move(bytes), stop_on_error);
  }
  // The other ranks' last units. Units are handed out in index order, so every unit before a
  // failed one was handed out before it and arrives: the prefix always completes.
  while (!halted && delivered < n) {
    {
      std::unique_lock lk(b.m);
      b.cv.wait_for(lk, std::chrono::milliseconds(50), [&] { return b.done.count(delivered) > 0; });
      progress.set(b.completed);
    }
    if (deliver()) halt();
  }
  if (comm.joinable()) comm.join();
#ifdef MILLNET_HAVE_MPI
  if (g_size > 1) {
    char failed = failure ? 1 : 0;
    MPI_Bcast(&failed, 1, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (failed) g_failure_shared = true;
  }
#endif
  progress.finish();
  stats.delivered = delivered;
  if (failure) std::rethrow_exception(failure);
  return stats;
}

void log_distribution(const std::string& what, const DistributeStats& s) {
  if (g_size <= 1 || g_rank != 0) return;
  const double per = s.remote_units ? static_cast<double>(s.bytes_to_root) / static_cast<double>(s.remote_units) : 0.0;
  info(what + ": " + std::to_string(s.units) + " work units over " + std::to_string(g_size) + " MPI ranks (" +
       std::to_string(s.units - s.remote_units) + " on rank 0); " + std::to_string(s.bytes_to_root) +
       " bytes gathered by rank 0 from the other ranks (" + std::to_string(static_cast<long long>(per + 0.5)) +
       " per unit they computed), " + std::to_string(s.bytes_from_root) + " bytes of unit indices sent");
}

void put_bytes(std::string& out, const std::string& s) {
  const std::uint64_t len = s.size();
  out.append(reinterpret_cast<const char*>(&len), 8);
  out += s;
}

std::string get_bytes(const std::string& in, std::size_t& pos) {
  std::uint64_t len = 0;
  if (pos + 8 > in.size()) throw Error("mpi: truncated result message");
  std::memcpy(&len, in.data() + pos, 8);
  pos += 8;
  if (len > in.size() - pos) throw Error("mpi: truncated result message");
  std::string s = in.substr(pos, static_cast<std::size_t>(len));
  pos += static_cast<std::size_t>(len);
  return s;
}

std::string pack_files(const std::string& dir) {
  // Inside an open OutputSet the writers leave "<name>.tmp-<pid>" (staged, not renamed).
  const std::string suffix = ".tmp-" + std::to_string(static_cast<long>(::getpid()));
  std::vector<std::pair<std::string, fs::path>> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    std::string rel = fs::relative(e.path(), dir).generic_string();
    if (rel.size() > suffix.size() && rel.compare(rel.size() - suffix.size(), suffix.size(), suffix) == 0)
      rel.resize(rel.size() - suffix.size());
    files.emplace_back(rel, e.path());
  }
  std::sort(files.begin(), files.end());
  std::string out;
  put_bytes(out, std::to_string(files.size()));
  for (const auto& [rel, path] : files) {
    put_bytes(out, rel);
    put_bytes(out, read_file(path));
  }
  return out;
}

namespace {
/// The process exists and is not a zombie (a killed rank stays one until its parent, or the
/// container's init, reaps it; kill(pid, 0) succeeds on it). Unsure (EPERM) counts as alive.
bool process_alive(long pid) {
  if (::kill(static_cast<pid_t>(pid), 0) != 0) return errno != ESRCH;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return true;
  const std::size_t close = line.rfind(')');  // "pid (comm) S ...": comm may hold spaces and parentheses
  return close == std::string::npos || close + 2 >= line.size() || line[close + 2] != 'Z';
}

/// Scratch folders of ranks that died (SIGKILL, the node's OOM killer, mpirun's SIGTERM after
/// another rank died: no destructor ran) are removed by the next run on the node: a folder
/// "millnet-unit-<pid>-<n>" whose process no longer exists. O(entries of the temporary folder),
/// once per process. A reused pid keeps its folder until that process is gone too.
void sweep_dead_scratch(const fs::path& tmp) {
  static std::once_flag once;
  std::call_once(once, [&] {
    std::error_code ec;
    for (fs::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (!name.starts_with("millnet-unit-")) continue;
      const std::string rest = name.substr(13);
      const std::size_t dash = rest.find('-');
      if (dash == std::string::npos || dash == 0) continue;
      long pid = 0;
      try {
        pid = std::stol(rest.substr(0, dash));
      } catch (...) {
        continue;
      }
      if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
      if (process_alive(pid)) continue;
      std::error_code rm;
      fs::remove_all(it->path(), rm);
    }
  });
}
}  // namespace

std::string write_and_pack(const std::function<void(const std::string& dir)>& write) {
  static std::atomic<unsigned> counter{0};
  sweep_dead_scratch(fs::temp_directory_path());
  const fs::path dir = fs::temp_directory_path() / ("millnet-unit-" + std::to_string(static_cast<long>(::getpid())) +
                                                    "-" + std::to_string(counter++));
  struct Cleanup {
    fs::path d;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(d, ec);
    }
  } cleanup{dir};
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string packed;
  {
    OutputSet scratch;  // dropped uncommitted: the staged temporaries go with the folder
    write(dir.string());
    packed = pack_files(dir.string());
  }
  return packed;
}

void unpack_files(const std::string& packed, const std::string& dir) {
  std::size_t pos = 0;
  const std::size_t count = std::stoul(get_bytes(packed, pos));
  for (std::size_t k = 0; k < count; ++k) {
    const std::string rel = get_bytes(packed, pos);
    const std::string bytes = get_bytes(packed, pos);
    write_file_atomic(fs::path(dir) / rel, bytes);
  }
}

}  // namespace millnet::app
