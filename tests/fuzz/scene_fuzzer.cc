// libFuzzer target: the scene builder fed valid configs with hostile values.
// A structure-aware mutator (scene_mutator.h) replaces one value of the
// input config by a hostile one (NaN, ±Inf, denormals, ±1e308, integers
// past 2^63, long or deeply nested arrays, wrong types). Every input goes
// through `camdyn validate` (read, validate, build the model, sample the
// profile; no simulation), which must end normally or with a camdyn error
// (fuzz_support.h). File names in the seeds
// resolve against the source tree (profiles/, studies/).
#include <cstddef>
#include <cstdint>

#include "cli/run_study.h"
#include "fuzz_support.h"
#include "scene_mutator.h"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  camdyn::fuzz::silence_streams();
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  return camdyn::fuzz::mutate_config_value(data, size, max_size, seed);
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  camdyn::StudyRequest request;
  request.json_text.assign(reinterpret_cast<const char*>(data), size);
  request.base_dir = camdyn::fuzz::Scratch::get().dir().string();
  request.out_dir = (camdyn::fuzz::Scratch::get().dir() / "out").string();
  request.jobs = 1;
  request.validate_only = true;
  camdyn::fuzz::expect_camdyn_errors_only([&] { camdyn::run_study(request); });
  return 0;
}
