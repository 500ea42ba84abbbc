// cam_outline (dynamics/cam_outline.h): the contour and the pitch curve the
// simulation sees, for a cam made from its law (the pitch curve tracked) and
// a cam given as its contour (the contour tracked), and a flat face.
#include "dynamics/cam_outline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dynamics/model.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn {
namespace {

/// Offsetting a curve by ρ ~ 1e-2 m along a unit normal computed in double
/// precision: the distance is ρ to a few ulps of the coordinates (~1e-17 m each).
constexpr double kOffsetTolerance = 1e-15;

Model model_of(const std::string& file) { return build_model(load_scene(file), file); }

TEST(CamOutline, RollerContourIsTheRollerRadiusInsideThePitchCurve) {
  const std::string file = kStudiesDir + "/quickstart.json";
  const Model model = model_of(file);
  const CamOutline o = cam_outline(model, 720);
  ASSERT_EQ(o.u.size(), 720U);
  ASSERT_EQ(o.pitch_x.size(), 720U);
  double min_pitch = INFINITY, max_pitch = 0.0;
  for (std::size_t i = 0; i < o.u.size(); ++i) {
    EXPECT_NEAR(std::hypot(o.pitch_x[i] - o.contour_x[i], o.pitch_y[i] - o.contour_y[i]), 0.01, kOffsetTolerance) << i;
    // The contour is inside: nearer the cam centre than the pitch curve.
    EXPECT_LT(std::hypot(o.contour_x[i], o.contour_y[i]), std::hypot(o.pitch_x[i], o.pitch_y[i])) << i;
    min_pitch = std::min(min_pitch, std::hypot(o.pitch_x[i], o.pitch_y[i]));
    max_pitch = std::max(max_pitch, std::hypot(o.pitch_x[i], o.pitch_y[i]));
  }
  // Centred roller: the pitch curve's radius is r_b + ρ + s, s from 0 to the 20 mm lift.
  EXPECT_NEAR(min_pitch, 0.05, 1e-15);
  EXPECT_NEAR(max_pitch, 0.07, 1e-9);  // sampled every 0.5° near the top of the rise
}

TEST(CamOutline, ContourCamKeepsItsFittedContour) {
  const std::string file = kStudiesDir + "/contour_cam/measured_roller_cam.json";
  const Model model = model_of(file);
  const CamOutline o = cam_outline(model, 90);
  const double rho = model.follower.radius;
  for (std::size_t i = 0; i < o.u.size(); ++i) {
    const Eigen::Vector2d c = model.contour->at(o.u[i]).r;
    EXPECT_EQ(o.contour_x[i], c.x()) << i;
    EXPECT_EQ(o.contour_y[i], c.y()) << i;
    EXPECT_NEAR(std::hypot(o.pitch_x[i] - c.x(), o.pitch_y[i] - c.y()), rho, kOffsetTolerance) << i;
  }
}

TEST(CamOutline, FlatFaceHasNoPitchCurve) {
  const std::string file = kStudiesDir + "/followers/translating_flat.json";
  const Model model = model_of(file);
  const CamOutline o = cam_outline(model, 36);
  EXPECT_EQ(o.contour_x.size(), 36U);
  EXPECT_TRUE(o.pitch_x.empty());
  for (std::size_t i = 0; i < o.u.size(); ++i) {
    const Eigen::Vector2d c = model.profile().at(o.u[i]).r;
    EXPECT_EQ(o.contour_x[i], c.x()) << i;
    EXPECT_EQ(o.contour_y[i], c.y()) << i;
  }
}

}  // namespace
}  // namespace camdyn
