// The statistics of an identification against hand-computed small cases: the
// straight-line fit y = a + b x at x = 0, 1, 2, 3, whose JᵀJ = [[4, 6], [6, 14]]
// has the inverse [[0.7, −0.3], [−0.3, 0.2]].
#include "optim/identify/identify_statistics.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace camdyn::optim {
namespace {

/// Rounding of a few products of numbers of order 1–100.
constexpr double kRounding = 1e-13;

Eigen::MatrixXd line_jacobian() {
  Eigen::MatrixXd j(4, 2);
  j << 1, 0, 1, 1, 1, 2, 1, 3;
  return j;
}

Eigen::MatrixXd normal_inverse() {
  Eigen::MatrixXd a(2, 2);
  a << 0.7, -0.3, -0.3, 0.2;
  return a;
}

void expect_matrix(const Eigen::MatrixXd& actual, const Eigen::MatrixXd& expected) {
  ASSERT_EQ(actual.rows(), expected.rows());
  ASSERT_EQ(actual.cols(), expected.cols());
  for (Eigen::Index i = 0; i < expected.rows(); ++i)
    for (Eigen::Index j = 0; j < expected.cols(); ++j) EXPECT_NEAR(actual(i, j), expected(i, j), kRounding) << i << j;
}

TEST(SandwichCovariance, OneGroupWithoutLossIsSigmaSquaredTimesTheInverseNormalMatrix) {
  // r ⟂ the columns, Σ r² = 4 over n − p = 2 degrees of freedom: σ² = 2.
  const std::vector<double> r{1, -1, -1, 1};
  const Eigen::MatrixXd cov =
      sandwich_covariance(normal_inverse(), line_jacobian(), r, std::vector<double>(4, 1.0), {4}, 2.0);
  expect_matrix(cov, 2.0 * normal_inverse());
}

TEST(SandwichCovariance, LossWeightsScaleTheResidualVariance) {
  // ψ = 0.5 r: σ² = 0.25 · 2.
  const std::vector<double> r{1, -1, -1, 1};
  const Eigen::MatrixXd cov =
      sandwich_covariance(normal_inverse(), line_jacobian(), r, std::vector<double>(4, 0.5), {4}, 2.0);
  expect_matrix(cov, 0.5 * normal_inverse());
}

TEST(SandwichCovariance, EachGroupHasItsOwnResidualVariance) {
  // Groups of two rows, each with 2 · 2/4 = 1 degree of freedom: σ₁² = 2, σ₂² = 8;
  // B = 2 J₁ᵀJ₁ + 8 J₂ᵀJ₂ = [[20, 42], [42, 106]], A B A = [[1.7, −0.9], [−0.9, 1.0]].
  const std::vector<double> r{1, -1, 2, -2};
  const Eigen::MatrixXd cov =
      sandwich_covariance(normal_inverse(), line_jacobian(), r, std::vector<double>(4, 1.0), {2, 2}, 2.0);
  Eigen::MatrixXd expected(2, 2);
  expected << 1.7, -0.9, -0.9, 1.0;
  expect_matrix(cov, expected);
}

TEST(Identifiability, IndependentColumnsHaveUnitSingularValues) {
  Eigen::MatrixXd j(3, 2);
  j << 3, 0, 0, -2e-3, 0, 0;  // units do not matter: the columns are scaled to unit norm
  const Identifiability id = identifiability(j, {1.0, 1.0}, 1e-9);
  EXPECT_NEAR(id.singular_values(0), 1.0, kRounding);
  EXPECT_NEAR(id.singular_values(1), 1.0, kRounding);
  EXPECT_NEAR(id.condition_number, 1.0, kRounding);
  EXPECT_FALSE(id.no_effect[0]);
  EXPECT_FALSE(id.no_effect[1]);
}

TEST(Identifiability, ProportionalColumnsAreRankDeficientAlongTheirDifference) {
  Eigen::MatrixXd j(3, 2);
  j << 1, 2, 1, 2, 1, 2;
  const Identifiability id = identifiability(j, {1.0, 1.0}, 1e-9);
  // Both unit columns are (1, 1, 1)/√3: singular values √2 and 0.
  EXPECT_NEAR(id.singular_values(0), std::sqrt(2.0), kRounding);
  EXPECT_NEAR(id.singular_values(1), 0.0, kRounding);
  EXPECT_TRUE(std::isinf(id.condition_number) || id.condition_number > 1e14);
  // The null direction is (1, −1)/√2 up to sign.
  EXPECT_NEAR(std::abs(id.directions(0, 1)), std::sqrt(0.5), kRounding);
  EXPECT_NEAR(id.directions(0, 1), -id.directions(1, 1), kRounding);
}

TEST(Identifiability, AParameterBelowTheToleranceHasNoEffect) {
  // RMS effect of the second: |J₂| · magnitude / √n = 1e-12 · 10 / 2 < 1e-9.
  Eigen::MatrixXd j(4, 2);
  j << 1, 1e-12, 1, 0, 1, 0, 1, 0;
  const Identifiability id = identifiability(j, {1.0, 10.0}, 1e-9);
  EXPECT_FALSE(id.no_effect[0]);
  EXPECT_TRUE(id.no_effect[1]);
  EXPECT_NEAR(id.singular_values(0), 1.0, kRounding);
  EXPECT_EQ(id.singular_values(1), 0.0);
  EXPECT_TRUE(std::isinf(id.condition_number));
}

}  // namespace
}  // namespace camdyn::optim
