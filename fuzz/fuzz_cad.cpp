// libFuzzer target: STEP and IGES (ingest_io: the pre-scan, then load_mesh on .step / .igs).
//
// What is fuzzed (issue 42): the pre-scan (ingest/io/cad_scan.hpp) on every input, in this process,
// where the sanitizers and the coverage see it; the whole load — frame check, pre-scan, and the read,
// transfer check, estimate and tessellation in the reader's child process (cad_isolate.hpp) — on one
// input in 16 (chosen by a hash of the bytes: the same inputs every run). Open CASCADE is not
// instrumented (Debian's build): coverage cannot guide the fuzzer into it, and a crash in it is what
// the child process is for. The child costs ≈ 50–100 ms per input under the sanitizers, so reading
// every input would take 20,000 × 0.08 s ≈ 27 minutes; one in 16 keeps CI's 20,000 inputs to a few.
// Coarse tessellation and small limits keep each read short.
//
// A finding: a sanitizer report or a crash in this process, an exception other than
// millnet::Error, or a child that ended without an answer (a sanitizer report in our code there: its
// ASan exits 1). A child that crashed inside Open CASCADE is a handled refusal, not a finding; with
// MILLNET_FUZZ_CAD_CRASHES=DIR set, its input is kept in DIR to become a named regression case.
#include "../ingest/io/cad_scan.hpp"
#include "fuzz_util.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ULL;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

void keep(const std::uint8_t* data, std::size_t size, std::uint64_t hash, const char* ext) {
  const char* dir = std::getenv("MILLNET_FUZZ_CAD_CRASHES");
  if (dir == nullptr) return;
  const std::string path = std::string(dir) + "/crash-" + std::to_string(hash) + ext;
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace millnet;
  const std::string_view text = fuzz::as_text(data, size);
  (void)ingest::detail::scan_step(text);
  (void)ingest::detail::scan_iges(text);
  const std::uint64_t hash = fnv1a(data, size);
  static const std::uint64_t one_in = [] {  // MILLNET_FUZZ_CAD_ONE_IN=1: every input read (long runs)
    const char* v = std::getenv("MILLNET_FUZZ_CAD_ONE_IN");
    return v ? std::max<std::uint64_t>(1, std::strtoull(v, nullptr, 10)) : 16;
  }();
  if (hash % one_in != 0) return 0;
  const bool step = text.substr(0, 4096).find("ISO-10303-21") != std::string_view::npos;
  ingest::CadOptions o;
  o.chord_tolerance_mm = 0.05;
  o.angular_deflection_rad = 0.5;
  o.timeout_s = 5;
  o.limits.max_work = 2e6;
  o.limits.max_memory_bytes = 512.0 * 1024 * 1024;
  return fuzz::expect_clean([&] {
    try {
      (void)ingest::load_mesh(fuzz::as_file(data, size, step ? ".step" : ".igs"), o);
    } catch (const Error& e) {
      const std::string what = e.what();
      if (what.find("reader ended without an answer") != std::string::npos) {
        std::fprintf(stderr, "fuzz_cad: %s\n", what.c_str());
        std::abort();  // a sanitizer report in the child (our code), or its own exit
      }
      if (what.find("reader crashed") != std::string::npos) keep(data, size, hash, step ? ".step" : ".igs");
      throw;
    }
  });
}
