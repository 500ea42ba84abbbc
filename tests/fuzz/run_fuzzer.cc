// libFuzzer target: past validation. A config (JSON text, the scene
// fuzzer's seeds and mutator: scene_mutator.h) is run as `camdyn run` runs
// it, on a study wall-time budget of kStudyBudgetS, so each input ends in
// milliseconds: the simulation loop, the study runners (simulate, compare,
// jump_map, periodic, convergence, speed_limit, optimize, identify) and
// every output writer they reach (CSV, JSON, the HTML report; gnuplot is
// replaced by a program that does not exist, so the report's placeholder
// path runs instead of a process per input). A run that stops on the budget
// is an ordinary end (exit 3); anything but a camdyn error is a finding
// (fuzz_support.h).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "cli/run_study.h"
#include "fuzz_support.h"
#include "scene_mutator.h"

namespace {

constexpr double kStudyBudgetS = 0.05;     // [s] wall time of a whole study (--max-study-time)
constexpr double kMemoryBudgetMb = 256.0;  // [MB] what the inputs may ask to hold (--max-memory)

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  camdyn::fuzz::silence_streams();
  setenv("CAMDYN_GNUPLOT", "/nonexistent/camdyn-fuzz-gnuplot", 1);
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  return camdyn::fuzz::mutate_config_value(data, size, max_size, seed);
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const camdyn::fuzz::Scratch& scratch = camdyn::fuzz::Scratch::get();
  scratch.clear();
  camdyn::StudyRequest request;
  request.json_text.assign(reinterpret_cast<const char*>(data), size);
  request.base_dir = scratch.dir().string();
  request.out_dir = (scratch.dir() / "out").string();
  request.jobs = 1;
  request.summary = false;
  request.max_study_time_s = kStudyBudgetS;
  request.max_memory_mb = kMemoryBudgetMb;
  camdyn::fuzz::expect_camdyn_errors_only([&] { camdyn::run_study(request); });
  return 0;
}
