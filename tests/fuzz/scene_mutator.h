// A structure-aware mutator for the targets that read one config as JSON
// text (scene_fuzzer, run_fuzzer; docs/fuzzing.md): it parses the input,
// picks one value (numbers preferred: they are what the physics reads) and
// replaces it by a hostile one: NaN, ±Inf (as 1e999 and as the strings
// "NaN"/"inf"), denormals, ±1e308, 0, -0, negative or rescaled numbers,
// integers past 2^53 and 2^63, a long array, or a deeply nested array; now
// and then, or when the input is not JSON, it falls back to libFuzzer's byte
// mutations.
#pragma once

#include <cstddef>
#include <cstdint>

namespace camdyn::fuzz {

/// The body of LLVMFuzzerCustomMutator (same arguments and result).
std::size_t mutate_config_value(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned int seed);

}  // namespace camdyn::fuzz
