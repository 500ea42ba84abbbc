// The public API seen as a caller sees it: this file includes only
// <camdyn/camdyn.h> (and GoogleTest), so it compiles only if the public
// headers are complete on their own; it uses nothing else of camdyn.
// (tests/CMakeLists.txt also compiles each public header alone.)
#include <camdyn/camdyn.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "study_paths.h"

namespace {

TEST(PublicHeaders, VersionComesFromTheProjectVersion) {
  EXPECT_STREQ(camdyn::kVersion, CAMDYN_VERSION);
  EXPECT_EQ(std::string(CAMDYN_VERSION), std::to_string(CAMDYN_VERSION_MAJOR) + "." +
                                             std::to_string(CAMDYN_VERSION_MINOR) + "." +
                                             std::to_string(CAMDYN_VERSION_PATCH));
}

TEST(PublicHeaders, ErrorsAreStandardExceptions) {
  static_assert(std::is_base_of_v<std::runtime_error, camdyn::InputError>);
  static_assert(std::is_base_of_v<std::runtime_error, camdyn::NumericalError>);
  const camdyn::InputError e("scene.json", "mechanism.cam.rpm", "must be > 0, got -1");
  EXPECT_STREQ(e.what(), "scene.json: mechanism.cam.rpm: must be > 0, got -1");
}

TEST(PublicHeaders, LoadSimulateAndReadTheResult) {
  const camdyn::Scene scene = camdyn::Scene::load(kQuickstart);
  EXPECT_EQ(scene.name(), "quickstart");
  EXPECT_EQ(scene.rpm(), 1300.0);
  EXPECT_TRUE(std::isfinite(scene.jump_speed_rpm()));
  const camdyn::Result result = camdyn::simulate(scene);
  EXPECT_TRUE(result.solver.converged()) << result.solver.message;
  EXPECT_STREQ(camdyn::termination_name(result.solver.termination), "converged");
  EXPECT_TRUE(result.solver.message.empty());
  EXPECT_GT(result.solver.steps, 0);
  // The quickstart runs above its jump speed: the follower separates and hammers back.
  EXPECT_GT(result.metrics.at("separation_fraction"), 0.0);
  EXPECT_GT(result.metrics.at("impact_count"), 0.0);
  EXPECT_EQ(result.metrics.at("jump_speed_rpm"), scene.jump_speed_rpm());
  EXPECT_GT(result.series.rows(), 0U);
  EXPECT_EQ(result.series["time"].size(), result.series.rows());
  EXPECT_THROW((void)result.series["no_such_column"], std::out_of_range);
  EXPECT_FALSE(result.events.empty());
  EXPECT_NO_THROW(camdyn::throw_if_failed(result));
}

TEST(PublicHeaders, ThrowIfFailedThrowsNumericalErrorWithTheMessage) {
  camdyn::Result result;
  result.solver.termination = camdyn::TerminationStatus::step_budget;
  result.solver.message = "more than 10 steps at t = 0.1 s";
  try {
    camdyn::throw_if_failed(result);
    FAIL() << "no NumericalError";
  } catch (const camdyn::NumericalError& e) {
    EXPECT_STREQ(e.what(), "more than 10 steps at t = 0.1 s");
  }
}

}  // namespace
