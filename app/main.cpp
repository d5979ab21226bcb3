// millnet command-line entry point: a thin CLI11 dispatcher. Each subcommand lives in app/cmd_*.cpp.
// Exit codes: 0 success, 1 bad input, flag values out of range included (one clear line on
// stderr), 2 usage error (unknown or missing flag; one line too).
#include "cli.hpp"
#include "mpi_cluster.hpp"

#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"
#include "millnet/core/output_set.hpp"

#include <chrono>
#include <iostream>
#include <thread>
#include <new>
#include <optional>

namespace {
/// Every error is one line on stderr, whatever text a library put into it.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  if (s.size() > 2000) s = s.substr(0, 1997) + "...";
  return s;
}
/// The command's one error line, and under MPI the end of every rank. Every rank reads the same
/// input and meets the same bad value: rank 0 says it once. A failure rank 0 broadcast at the end of
/// a distribution (a part that stops `dataset`) ends every rank together; any other failure ends
/// the run with MPI_Abort, since the other ranks may be waiting for this one in a distribution
/// (rank 0 failing to create --out while the others start on the parts). A rank other than 0 that
/// fails alone says why, with its rank, after a grace second (when every rank fails alike, rank
/// 0's abort ends it first and the line is said once).
int fail(const std::string& cmd, const std::string& what) {
  using namespace millnet::app;
  // Each line goes out in one write (one string to the unbuffered stream): under mpirun the ranks'
  // stderr is forwarded in the chunks written, and its MPI_ABORT banner landed between "millnet "
  // and the rest of a line written piecewise (seen in a -j2 test run).
  if (cluster_root()) std::cerr << ("millnet " + cmd + ": error: " + what + "\n");
  if (cluster_size() > 1 && !cluster_failure_shared()) {
    if (!cluster_root()) {
      std::this_thread::sleep_for(std::chrono::seconds(1));
      std::cerr << ("millnet " + cmd + ": error on MPI rank " + std::to_string(cluster_rank()) + ": " + what + "\n");
    }
    cluster_abort(1);
  }
  return 1;
}
}  // namespace

int main(int argc, char** argv) {
  using namespace millnet::app;
  cluster_init(argc, argv);  // MPI only under a launcher (mpirun, srun); one rank otherwise
  CLI::App app{"millnet — strategy learning and pocket roughing for CAM engineers", "millnet"};
  app.set_version_flag("--version", std::string(MILLNET_VERSION));
  app.require_subcommand(1);
  // One line per usage error (CLI11's default adds "Run with --help for more information." on a second).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "millnet: usage error: " + std::string(e.what()) + " (see --help)\n";
  });
  std::vector<Registered> commands;
  auto add = [&](Registered (*reg)(CLI::App&)) { commands.push_back(reg(app)); };
  add(register_sample);
  add(register_dataset);
  add(register_train);
  add(register_predict);
  add(register_pocket);
  add(register_compare);
  add(register_rough);
  add(register_finish);
  add(register_simulate);
  add(register_run);
  add(register_job);
  add(register_view);
  add(register_tools);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ValidationError& e) {
    // A flag's value out of its range (NaN, 1e308, --threads 100000): bad input like a bad config
    // value, so one line and exit 1 (issue 15); unknown flags and missing ones stay usage errors.
    std::string who = "millnet";
    for (const auto& c : commands)
      if (c.sub->parsed()) who += " " + c.sub->get_name();
    if (cluster_root())
      std::cerr << (who + ": error: " + e.what() + "\n");  // every rank parsed the same words; one write
    return 1;
  } catch (const CLI::ParseError& e) {
    if (!cluster_root()) return e.get_exit_code() == 0 ? 0 : 2;
    const int code = app.exit(e);  // prints help/version (code 0) or the usage error
    return code == 0 ? 0 : 2;
  }
  for (auto& [sub, body] : commands) {
    if (!sub->parsed()) continue;
    const std::string cmd = sub->get_name();
    const bool all_or_nothing = cmd != "run" && cmd != "dataset";
    try {
      // A command's outputs are committed together when it returns, or not at all when it throws
      // (issue 15; core/output_set.hpp). `dataset` and `run` write caches that their later stages
      // read back by path; they check their inputs before writing instead.
      if (cluster_size() > 1 && cmd != "dataset" && cmd != "predict" && cmd != "finish")
        throw millnet::Error(
            "runs on one process: under mpirun only dataset, predict and finish share their work "
            "over the ranks (started on " +
            std::to_string(cluster_size()) + " ranks, every one would write the same files); run it without mpirun");
      std::optional<millnet::OutputSet> outputs;
      if (all_or_nothing) outputs.emplace();
      const int code = body();
      if (outputs) outputs->commit();
      return code;
    } catch (const millnet::Error& e) {
      return fail(cmd, one_line(e.what()));
    } catch (const std::bad_alloc&) {
      // Not the library's "std::bad_alloc" (tests/corpus/cli/out_of_memory.args).
      return fail(cmd, "out of memory while running " + cmd + " on these inputs" +
                           (all_or_nothing ? "; nothing was written" : "") +
                           " (smaller inputs or settings, or more memory)");
    } catch (const std::exception& e) {
      // A library's exception that no reader turned into a millnet::Error: at least without its
      // "[json.exception.type_error.302] " prefix.
      const std::string what = e.what();
      return fail(cmd, one_line(what.rfind("[json.exception", 0) == 0 ? millnet::json_error_text(what) : what));
    }
  }
  return 2;
}
