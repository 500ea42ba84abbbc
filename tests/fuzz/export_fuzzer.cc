// libFuzzer target: the manufacturing export (`camdyn export`,
// docs/export.md). The input picks one of the committed follower studies
// (translating roller, flat face and mushroom, oscillating roller and flat
// face) and fuzzes the cam's base radius, the
// sampling (point count, chord tolerance), the cutter radius, and the
// radius and angle step of the follower lift table; then the profile is
// sampled and profile.csv, profile.dxf (dxflib) and follower_lift.csv are
// written into the process's private scratch folder. Every step must end
// normally or with a camdyn error (fuzz_support.h). Valid sizes are kept
// below kMaxFuzzedCount (see there).
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/constants.h"
#include "dynamics/model.h"
#include "fuzz_support.h"
#include "io/config.h"
#include "output/profile_export.h"
#include "scene/scene.h"

namespace {

using camdyn::kTwoPi;

// Relative to the source tree (CAMDYN_SOURCE_DIR).
// Not the contour cam (studies/contour_cam): each of its profile points is a
// contact solve, 2 ms under ASan, so ordinary sizes pass libFuzzer's -timeout
// (docs/fuzzing.md, "Findings open").
constexpr const char* kStudies[] = {
    "studies/quickstart.json", "studies/followers/translating_flat.json", "studies/followers/translating_mushroom.json",
    "studies/followers/oscillating_roller.json", "studies/followers/oscillating_flat.json"};

constexpr double kOneDegree = 0.017453292519943295;  // [rad]
// Valid counts (points, lift-table rows) stay below this: the 1,000,000
// allowed take seconds under ASan, past libFuzzer's -timeout on a busy
// machine. Counts past the limit are still fuzzed: they must be refused.
constexpr int kMaxFuzzedCount = 2000;
// Valid chord tolerances [m] below kMinFuzzedChord are raised to it, for the same reason.
constexpr double kMinAllowedChord = camdyn::ProfileOutputConfig::kMinChordToleranceMm * 1e-3;
constexpr double kMinFuzzedChord = 1e-7;

struct Study {
  std::string file;
  camdyn::Json doc;                      ///< the config with `extends` resolved
  std::optional<camdyn::Model> nominal;  ///< built once, for the inputs that keep the base radius
  std::string name;
};

std::vector<Study>& studies() {
  static std::vector<Study> loaded;
  return loaded;
}

// A length (or angle) near `nominal` most of the time, else a hostile value.
double fuzzed_value(FuzzedDataProvider& in, double nominal) {
  switch (in.ConsumeIntegralInRange(0, 7)) {
    case 0:
      return in.ConsumeFloatingPoint<double>();  // anything, ±1e308 included
    case 1:
      return in.PickValueInArray({0.0, -0.0, -nominal, std::numeric_limits<double>::quiet_NaN(),
                                  std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                  std::numeric_limits<double>::denorm_min(), 1e-300, 1e300});
    case 2:
      return nominal * std::pow(10.0, in.ConsumeFloatingPointInRange(-12.0, 12.0));
    default:
      return nominal * in.ConsumeFloatingPointInRange(0.0, 4.0);
  }
}

// The point count of the profile: a valid one up to kMaxFuzzedCount, or one that is refused.
int fuzzed_points(FuzzedDataProvider& in) {
  if (in.ConsumeBool()) return in.ConsumeIntegralInRange(-4, kMaxFuzzedCount);
  return in.PickValueInArray({0, -1, camdyn::ProfileOutputConfig::kMaxPoints + 1, std::numeric_limits<int>::max(),
                              std::numeric_limits<int>::min()});
}

// The lift table's angle step [rad]: valid steps give at most kMaxFuzzedCount rows.
double fuzzed_angle_step(FuzzedDataProvider& in) {
  const double step = fuzzed_value(in, kOneDegree);
  if (!(step > 0.0) || step >= kTwoPi / kMaxFuzzedCount) return step;
  return in.ConsumeBool() ? kTwoPi / kMaxFuzzedCount : kTwoPi / (2.0 * camdyn::ProfileOutputConfig::kMaxPoints);
}

void export_profile(const camdyn::Model& model, const std::string& name, FuzzedDataProvider& in) {
  camdyn::ProfileOptions options;
  if (in.ConsumeBool()) options.points = fuzzed_points(in);
  options.chord_tolerance = fuzzed_value(in, 1e-6);  // [m]
  if (options.chord_tolerance >= kMinAllowedChord && options.chord_tolerance < kMinFuzzedChord)
    options.chord_tolerance = kMinFuzzedChord;
  if (in.ConsumeBool()) options.cutter_radius = fuzzed_value(in, 5e-3);  // [m]
  const double follower_radius = fuzzed_value(in, 1e-2);                 // [m]
  const double angle_step = fuzzed_angle_step(in);
  const camdyn::fuzz::Scratch& scratch = camdyn::fuzz::Scratch::get();
  camdyn::fuzz::expect_camdyn_errors_only([&] {
    const camdyn::SampledCamProfile profile = camdyn::sample_cam_profile(model, options, camdyn::ProfileOptionNames{});
    camdyn::write_profile_files(scratch.dir(), profile, name, {camdyn::ProfileFormat::csv, camdyn::ProfileFormat::dxf});
  });
  camdyn::fuzz::expect_camdyn_errors_only([&] {
    const camdyn::FollowerLiftTable table = camdyn::follower_lift_table(model, follower_radius, angle_step, "");
    camdyn::write_follower_lift_csv(scratch.dir() / "follower_lift.csv", table, name);
  });
}

// The scene of a study as `camdyn export` reads it (its mechanism, as a
// simulate scene), the base radius fuzzed.
camdyn::SceneConfig export_scene(const Study& study, FuzzedDataProvider& in) {
  camdyn::Json doc = study.doc;
  camdyn::Json& cam = doc["mechanism"]["cam"];
  if (cam.contains("base_radius")) cam["base_radius"] = fuzzed_value(in, cam["base_radius"].get<double>());
  return camdyn::scene_from_json(doc, camdyn::config_source(study.file));
}

// Half the inputs keep the base radius: building the cam costs more than the export.
void export_study(const Study& study, FuzzedDataProvider& in) {
  if (in.ConsumeBool()) {
    export_profile(*study.nominal, study.name, in);
    return;
  }
  const camdyn::SceneConfig scene = export_scene(study, in);
  const camdyn::Model model = camdyn::build_model(scene, study.file);
  export_profile(model, scene.name, in);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  camdyn::fuzz::silence_streams();
  for (const char* file : kStudies) {
    Study study;
    study.file = std::string(CAMDYN_SOURCE_DIR) + "/" + file;
    study.doc = camdyn::load_config_json(study.file);
    study.doc["study"] = "simulate";
    const camdyn::SceneConfig scene = camdyn::scene_from_json(study.doc, camdyn::config_source(study.file));
    study.nominal = camdyn::build_model(scene, study.file);
    study.name = scene.name;
    studies().push_back(std::move(study));
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Study& study = studies()[in.ConsumeIntegralInRange<std::size_t>(0, studies().size() - 1)];
  camdyn::fuzz::Scratch::get().clear();
  camdyn::fuzz::expect_camdyn_errors_only([&] { export_study(study, in); });
  return 0;
}
