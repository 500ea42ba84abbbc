// libFuzzer target: the CSV readers. The input is written as data.csv to a
// scratch folder and read as the loader reads it
//   * as a lift table (`motion_law.table`, columns angle_deg and lift:
//     io/config.h load_table_rows), which build_motion_law then fits with a
//     periodic spline, and
//   * as an identification record (`reference.file`, columns time and
//     force_N: optim/identify/measured_record.h read_reference) of a 1 s run.
// Seeds carry all four columns (tests/fuzz/corpus/csv). Each read must end
// normally or with a camdyn error (fuzz_support.h). (The config_fuzzer
// reaches the same readers through whole configs, at a tenth of the speed.)
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_support.h"
#include "geometry/motion_law.h"
#include "io/config.h"
#include "optim/identify/identify.h"

namespace {

constexpr double kRunEnd = 1.0;  // [s] the simulated run the record must lie in

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  camdyn::fuzz::silence_streams();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const camdyn::fuzz::Scratch& scratch = camdyn::fuzz::Scratch::get();
  const std::string file =
      scratch.write("data.csv", std::string_view(reinterpret_cast<const char*>(data), size)).string();
  camdyn::fuzz::expect_camdyn_errors_only([&] {
    camdyn::MotionLawConfig law;
    law.table = camdyn::TableConfig{.file = file};
    camdyn::load_table_rows(*law.table);
    camdyn::build_motion_law(law, "fuzz.json");
  });
  camdyn::fuzz::expect_camdyn_errors_only([&] {
    camdyn::optim::ReferenceSpec reference;
    reference.file = file;
    reference.signals = {{"contact_force", "force_N"}};
    camdyn::optim::read_reference(reference, kRunEnd);
  });
  return 0;
}
