// millnet rough | run (written next).
#include "cli.hpp"

namespace millnet::app {
Registered register_rough(CLI::App& app) {
  Common* c = new Common;
  CLI::App* sub = app.add_subcommand("rough", "Z-level roughing of a part's mesh");
  add_common(sub, *c);
  return {sub, []() { return 2; }};
}
Registered register_run(CLI::App& app) {
  Common* c = new Common;
  CLI::App* sub = app.add_subcommand("run", "dataset → train → predict → rough");
  add_common(sub, *c);
  return {sub, []() { return 2; }};
}
}  // namespace millnet::app
