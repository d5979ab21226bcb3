#pragma once
// Many processes, one command (issue 10): `mpirun -np K millnet dataset|predict|finish …`.
//
// MPI is private to app/mpi_cluster.cpp (and absent from a build without MILLNET_MPI: one rank).
// It is started only when a launcher says so in the environment (OMPI_COMM_WORLD_SIZE, PMIX_RANK,
// PMI_RANK or PMI_SIZE: mpirun, or srun with PMI/PMIx); without one the executable runs as one rank
// and never touches MPI, exactly as before (tests, fuzzers and scripts unaffected).
//
// distribute(): work units 0..n-1 are handed out one at a time on request (dynamic load balancing:
// parts differ in cost by orders of magnitude). Rank 0 computes units too, while a communication
// thread of its own (the only thread that calls MPI during a distribution) answers the other ranks.
// Results are delivered on rank 0 in unit-index order, each as soon as every unit before it is in,
// so the outputs are the bytes of a one-rank run whatever K, the thread count or the arrival order.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace millnet::app {

/// Starts MPI when a launcher's environment asks for it. Call once, first thing in main.
void cluster_init(int& argc, char**& argv);
/// Ends MPI (if started). Called at exit; safe to call twice.
void cluster_finalize();
/// True once a distribution has ended in a failure that rank 0 broadcast to every rank (each
/// leaves the command together: rank 0 with the error, the others quietly).
[[nodiscard]] bool cluster_failure_shared();
/// Ends every rank at once (MPI_Abort) when a rank fails outside a shared failure: a rank that
/// stops alone would leave the others waiting for it in a distribution. No-op on one rank.
void cluster_abort(int code);
[[nodiscard]] int cluster_rank();
[[nodiscard]] int cluster_size();
[[nodiscard]] inline bool cluster_root() { return cluster_rank() == 0; }

/// One unit's computation, on any rank: its result as bytes; throws on failure (the message is
/// delivered to rank 0 as the unit's error).
using UnitWork = std::function<std::string(std::size_t index)>;
/// Rank 0 only, in index order: the unit's bytes (ok) or its error text (!ok).
using UnitResult = std::function<void(std::size_t index, bool ok, std::string&& bytes)>;

struct DistributeStats {
  std::size_t units = 0, delivered = 0;
  std::size_t remote_units = 0;       ///< units computed by ranks other than 0
  std::uint64_t bytes_to_root = 0;    ///< result messages received by rank 0 (headers included)
  std::uint64_t bytes_from_root = 0;  ///< index messages sent by rank 0
};

/// Runs units 0..n-1 over every rank (collective: every rank calls it with the same n). With
/// stop_on_error, the first failed unit in index order stops the hand-out: on_result gets that
/// failure and nothing after it. An exception thrown by on_result stops the hand-out, lets the
/// other ranks finish their current unit, and is rethrown on rank 0. `label` names the progress
/// line (units done across all ranks). Returns the same stats on rank 0; zeros elsewhere.
DistributeStats distribute(std::size_t n, const UnitWork& work, const UnitResult& on_result, bool stop_on_error,
                           const std::string& label);

/// One information line on rank 0 of a run with several ranks: units, ranks, bytes each way.
void log_distribution(const std::string& what, const DistributeStats& stats);

/// The files a unit wrote below `dir`, packed as bytes (relative name + content, sorted by name),
/// and written back below another folder on rank 0 (write_file_atomic, so inside the command's
/// OutputSet). Used to ship a part's programs, metrics and pictures to rank 0.
[[nodiscard]] std::string pack_files(const std::string& dir);
void unpack_files(const std::string& packed, const std::string& dir);

/// Runs `write(dir)` with dir a fresh scratch folder (under the system's temporary folder, inside
/// an OutputSet that is never committed, so nothing reaches the command's outputs), returns
/// pack_files of what it wrote and removes the folder, also when `write` throws.
[[nodiscard]] std::string write_and_pack(const std::function<void(const std::string& dir)>& write);

/// Appends/reads length-prefixed strings (the payloads' framing).
void put_bytes(std::string& out, const std::string& s);
[[nodiscard]] std::string get_bytes(const std::string& in, std::size_t& pos);

/// How a unit's value travels between ranks (e.g. CBOR of its figures: doubles bit for bit).
template <class T>
struct UnitCodec {
  std::string (*encode)(const T&);
  T (*decode)(const std::string&);
};

/// A unit's outcome on rank 0: its value, or the error it failed with; `files` are what it wrote,
/// packed (pack_files), for the caller to unpack below its output folder — or to drop, when the
/// part the unit belongs to failed (a batch writes each good part completely and nothing of a bad
/// one).
template <class T>
struct UnitOutcome {
  std::optional<T> value;
  std::string error;
  std::string files;
};

/// distribute() with typed results: one code path for one process and for many (issue 36). Unit
/// i's work(i, dir) writes its files below `dir` (a scratch folder of its own) and returns a value;
/// take(i, outcome) runs on rank 0 in unit order with the value (encoded and decoded only between
/// ranks), the error, and the packed files. Collective like distribute().
template <class T>
DistributeStats distribute_typed(std::size_t n, const std::function<T(std::size_t, const std::string& dir)>& work,
                                 const std::function<void(std::size_t, UnitOutcome<T>&&)>& take, bool stop_on_error,
                                 const std::string& label, UnitCodec<T> codec) {
  std::vector<std::optional<T>> local(cluster_size() == 1 ? n : 0);  // one rank: values stay in memory
  const UnitWork bytes_work = [&](std::size_t i) {
    std::optional<T> value;
    std::string msg;
    put_bytes(msg, write_and_pack([&](const std::string& dir) { value.emplace(work(i, dir)); }));
    if (local.empty()) {
      put_bytes(msg, codec.encode(*value));
    } else {
      local[i] = std::move(value);
    }
    return msg;
  };
  const UnitResult bytes_take = [&](std::size_t i, bool ok, std::string&& bytes) {
    UnitOutcome<T> o;
    if (!ok) {
      o.error = std::move(bytes);
    } else {
      std::size_t pos = 0;
      o.files = get_bytes(bytes, pos);
      if (local.empty()) {
        o.value.emplace(codec.decode(get_bytes(bytes, pos)));
      } else {
        o.value = std::move(local[i]);
        local[i].reset();
      }
    }
    take(i, std::move(o));
  };
  return distribute(n, bytes_work, bytes_take, stop_on_error, label);
}

}  // namespace millnet::app
