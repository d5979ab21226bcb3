#pragma once
// millnet's error policy, written once (ARCHITECTURE.md):
//  * contract and input violations at a module boundary throw millnet::Error whose message names
//    the context (file, line, JSON key) and what was expected;
//  * expected empty results (no tool point fits, nothing to cut) come back as a status value the
//    caller must look at, never as an exception and never as a silently empty output;
//  * internal invariants use MILLNET_ASSERT, active in debug and sanitizer builds.
#include <stdexcept>
#include <string>

namespace millnet {

class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Error about a file: "<path>: <what>".
[[nodiscard]] inline Error file_error(const std::string& path, const std::string& what) {
  return Error(path + ": " + what);
}

/// Error about a line of a text file: "<path>:<line>: <what>" (line is 1-based).
[[nodiscard]] inline Error line_error(const std::string& path, long line, const std::string& what) {
  return Error(path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace millnet

#if !defined(NDEBUG) || defined(MILLNET_ASSERTS)
#define MILLNET_ASSERT(cond, msg)                                                                           \
  do {                                                                                                      \
    if (!(cond))                                                                                            \
      throw ::millnet::Error(std::string("internal invariant violated: ") + (msg) + " (" + __FILE__ + ":" + \
                             std::to_string(__LINE__) + ")");                                               \
  } while (0)
#else
#define MILLNET_ASSERT(cond, msg) ((void)0)
#endif
