// The compiled copies of SUNDIALS' serial vector kernels and banded LU
// (integrate/sundials_compiled_ops.h) against SUNDIALS' own, to the bit: every
// special case of the linear sum and scale, the norms, and a pivoting banded
// factorisation and solve.
#include "integrate/sundials_compiled_ops.h"

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "dynamics/simulation.h"
#include "tests/dynamics/scenes.h"

namespace camdyn {
namespace {

constexpr sunindextype kLength = 19;  // an 8-coil train's state

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

class CompiledOps : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(SUNContext_Create(nullptr, &context_), 0);
    for (N_Vector* v : {&x_, &y_, &z_, &w_}) *v = N_VNew_Serial(kLength, context_);
    for (N_Vector* v : {&fx_, &fy_, &fz_, &fw_}) {
      *v = N_VNew_Serial(kLength, context_);
      use_compiled_vector_ops(*v);
    }
    std::mt19937 rng(38);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (sunindextype i = 0; i < kLength; ++i) {
      NV_Ith_S(x_, i) = NV_Ith_S(fx_, i) = u(rng);
      NV_Ith_S(y_, i) = NV_Ith_S(fy_, i) = u(rng);
      NV_Ith_S(w_, i) = NV_Ith_S(fw_, i) = 1.0 / (1e-12 + 1e-8 * std::abs(u(rng)));
    }
  }
  void TearDown() override {
    for (N_Vector v : {x_, y_, z_, w_, fx_, fy_, fz_, fw_}) N_VDestroy(v);
    SUNContext_Free(&context_);
  }
  // Every element of a SUNDIALS vector and its compiled twin equal to the bit.
  static void expect_same(N_Vector a, N_Vector b) {
    for (sunindextype i = 0; i < kLength; ++i)
      EXPECT_TRUE(same_bits(NV_Ith_S(a, i), NV_Ith_S(b, i))) << i << ": " << NV_Ith_S(a, i) << " vs " << NV_Ith_S(b, i);
  }
  // Restores x, y (an in-place operation changed them).
  void reset() {
    for (sunindextype i = 0; i < kLength; ++i) {
      NV_Ith_S(fx_, i) = NV_Ith_S(x_, i);
      NV_Ith_S(fy_, i) = NV_Ith_S(y_, i);
    }
  }

  SUNContext context_ = nullptr;
  N_Vector x_ = nullptr, y_ = nullptr, z_ = nullptr, w_ = nullptr;      // SUNDIALS' kernels
  N_Vector fx_ = nullptr, fy_ = nullptr, fz_ = nullptr, fw_ = nullptr;  // the compiled ones
};

TEST_F(CompiledOps, LinearSumEveryCaseMatchesSundialsToTheBit) {
  const std::vector<std::pair<double, double>> cases = {{1.0, 1.0},  {1.0, -1.0}, {-1.0, 1.0}, {1.0, 0.3},
                                                        {0.3, 1.0},  {-1.0, 0.3}, {0.3, -1.0}, {0.7, 0.7},
                                                        {0.7, -0.7}, {0.3, 2.5},  {0.0, 2.5},  {-1.0, -1.0}};
  for (const auto& [a, b] : cases) {
    SCOPED_TRACE(testing::Message() << "a = " << a << ", b = " << b);
    N_VLinearSum_Serial(a, x_, b, y_, z_);
    N_VLinearSum(a, fx_, b, fy_, fz_);
    expect_same(z_, fz_);
    // In place: y ← a x + y and x ← x + b y (the axpy shortcuts).
    N_Vector y_copy = N_VClone(y_), x_copy = N_VClone(x_);
    N_VScale_Serial(1.0, y_, y_copy);
    N_VScale_Serial(1.0, x_, x_copy);
    N_VLinearSum_Serial(a, x_, b, y_copy, y_copy);
    N_VLinearSum(a, fx_, b, fy_, fy_);
    expect_same(y_copy, fy_);
    reset();
    N_VLinearSum_Serial(a, x_copy, b, y_, x_copy);
    N_VLinearSum(a, fx_, b, fy_, fx_);
    expect_same(x_copy, fx_);
    reset();
    N_VDestroy(y_copy);
    N_VDestroy(x_copy);
  }
}

TEST_F(CompiledOps, ElementwiseOperationsAndNormsMatchSundialsToTheBit) {
  for (double c : {1.0, -1.0, 0.37}) {
    N_VScale_Serial(c, x_, z_);
    N_VScale(c, fx_, fz_);
    expect_same(z_, fz_);
  }
  N_VScale_Serial(0.37, z_, z_);
  N_VScale(0.37, fz_, fz_);
  expect_same(z_, fz_);
  N_VProd_Serial(x_, y_, z_);
  N_VProd(fx_, fy_, fz_);
  expect_same(z_, fz_);
  N_VDiv_Serial(x_, y_, z_);
  N_VDiv(fx_, fy_, fz_);
  expect_same(z_, fz_);
  N_VAbs_Serial(x_, z_);
  N_VAbs(fx_, fz_);
  expect_same(z_, fz_);
  N_VInv_Serial(x_, z_);
  N_VInv(fx_, fz_);
  expect_same(z_, fz_);
  N_VAddConst_Serial(x_, 0.25, z_);
  N_VAddConst(fx_, 0.25, fz_);
  expect_same(z_, fz_);
  N_VConst_Serial(1.5, z_);
  N_VConst(1.5, fz_);
  expect_same(z_, fz_);
  EXPECT_TRUE(same_bits(N_VWrmsNorm_Serial(x_, w_), N_VWrmsNorm(fx_, fw_)));
  EXPECT_TRUE(same_bits(N_VWSqrSumLocal_Serial(x_, w_), N_VWSqrSumLocal(fx_, fw_)));
  EXPECT_TRUE(same_bits(N_VMaxNorm_Serial(x_), N_VMaxNorm(fx_)));
  EXPECT_TRUE(same_bits(N_VMin_Serial(x_), N_VMin(fx_)));
  // A clone carries the compiled operations (CVodeInit clones its state vector).
  N_Vector clone = N_VClone(fx_);
  EXPECT_EQ(clone->ops->nvlinearsum, fx_->ops->nvlinearsum);
  EXPECT_NE(clone->ops->nvlinearsum, x_->ops->nvlinearsum);
  N_VDestroy(clone);
}

TEST_F(CompiledOps, BandedFactorAndSolveMatchSundialsToTheBit) {
  constexpr sunindextype kBand = 3;  // an 8-coil train's half-bandwidth
  SUNMatrix a = SUNBandMatrix(kLength, kBand, kBand, context_);
  SUNMatrix fa = SUNBandMatrix(kLength, kBand, kBand, context_);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (sunindextype j = 0; j < kLength; ++j)
    for (sunindextype i = std::max<sunindextype>(0, j - kBand); i <= std::min(kLength - 1, j + kBand); ++i)
      // Off-diagonals as large as the diagonal: rows are swapped (partial pivoting).
      SM_ELEMENT_B(a, i, j) = SM_ELEMENT_B(fa, i, j) = (i == j ? 0.2 : 1.0) * u(rng);
  SUNLinearSolver s = SUNLinSol_Band(x_, a, context_);
  SUNLinearSolver fs = SUNLinSol_Band(fx_, fa, context_);
  use_compiled_band_solver(fs);
  ASSERT_EQ(SUNLinSolInitialize(s), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolInitialize(fs), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSetup(s, a), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSetup(fs, fa), SUNLS_SUCCESS);
  const auto* pivots = static_cast<SUNLinearSolverContent_Band>(s->content)->pivots;
  const auto* fpivots = static_cast<SUNLinearSolverContent_Band>(fs->content)->pivots;
  int swaps = 0;
  for (sunindextype k = 0; k < kLength; ++k) {
    EXPECT_EQ(pivots[k], fpivots[k]);
    swaps += pivots[k] != k ? 1 : 0;
  }
  EXPECT_GT(swaps, 0);
  ASSERT_EQ(SUNLinSolSolve(s, a, z_, y_, 0.0), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSolve(fs, fa, fz_, fy_, 0.0), SUNLS_SUCCESS);
  expect_same(z_, fz_);
  // The solve solves: A z = y to rounding (the factors were not the matrix).
  SUNMatrix check = SUNBandMatrix(kLength, kBand, kBand, context_);
  std::mt19937 again(7);
  for (sunindextype j = 0; j < kLength; ++j)
    for (sunindextype i = std::max<sunindextype>(0, j - kBand); i <= std::min(kLength - 1, j + kBand); ++i)
      SM_ELEMENT_B(check, i, j) = (i == j ? 0.2 : 1.0) * u(again);
  ASSERT_EQ(SUNMatMatvec(check, fz_, fw_), SUNMAT_SUCCESS);
  for (sunindextype i = 0; i < kLength; ++i) EXPECT_NEAR(NV_Ith_S(fw_, i), NV_Ith_S(y_, i), 1e-10);
  // A zero pivot is reported as SUNDIALS reports it.
  SUNMatZero(fa);
  EXPECT_EQ(SUNLinSolSetup(fs, fa), SUNLS_LUFACT_FAIL);
  for (SUNLinearSolver v : {s, fs}) SUNLinSolFree(v);
  for (SUNMatrix m : {a, fa, check}) SUNMatDestroy(m);
}

TEST_F(CompiledOps, DenseFactorAndSolveMatchSundialsToTheBit) {
  SUNMatrix a = SUNDenseMatrix(kLength, kLength, context_);
  SUNMatrix fa = SUNDenseMatrix(kLength, kLength, context_);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (sunindextype j = 0; j < kLength; ++j)
    for (sunindextype i = 0; i < kLength; ++i)
      SM_ELEMENT_D(a, i, j) = SM_ELEMENT_D(fa, i, j) = (i == j ? 0.1 : 1.0) * u(rng);
  SUNLinearSolver s = SUNLinSol_Dense(x_, a, context_);
  SUNLinearSolver fs = SUNLinSol_Dense(fx_, fa, context_);
  use_compiled_dense_solver(fs);
  ASSERT_EQ(SUNLinSolSetup(s, a), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSetup(fs, fa), SUNLS_SUCCESS);
  const auto* pivots = static_cast<SUNLinearSolverContent_Dense>(s->content)->pivots;
  const auto* fpivots = static_cast<SUNLinearSolverContent_Dense>(fs->content)->pivots;
  int swaps = 0;
  for (sunindextype k = 0; k < kLength; ++k) {
    EXPECT_EQ(pivots[k], fpivots[k]);
    swaps += pivots[k] != k ? 1 : 0;
  }
  EXPECT_GT(swaps, 0);
  for (sunindextype j = 0; j < kLength; ++j)
    for (sunindextype i = 0; i < kLength; ++i)
      EXPECT_TRUE(same_bits(SM_ELEMENT_D(a, i, j), SM_ELEMENT_D(fa, i, j))) << i << ", " << j;
  ASSERT_EQ(SUNLinSolSolve(s, a, z_, y_, 0.0), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSolve(fs, fa, fz_, fy_, 0.0), SUNLS_SUCCESS);
  expect_same(z_, fz_);
  SUNMatZero(fa);
  EXPECT_EQ(SUNLinSolSetup(fs, fa), SUNLS_LUFACT_FAIL);
  for (SUNLinearSolver v : {s, fs}) SUNLinSolFree(v);
  for (SUNMatrix m : {a, fa}) SUNMatDestroy(m);
}

/// The run with SUNDIALS' own kernels and with the compiled ones.
std::pair<SimulationResult, SimulationResult> both_ways(const SceneConfig& scene) {
  set_compiled_kernels_enabled(false);
  SimulationResult own = simulate_scene(scene, "test");
  set_compiled_kernels_enabled(true);
  SimulationResult compiled = simulate_scene(scene, "test");
  return {std::move(own), std::move(compiled)};
}

void expect_same_run(const SimulationResult& own, const SimulationResult& compiled) {
  ASSERT_EQ(own.solver.termination, Termination::converged);
  ASSERT_EQ(compiled.solver.termination, Termination::converged);
  EXPECT_EQ(own.solver.counters.steps, compiled.solver.counters.steps);
  EXPECT_EQ(own.solver.counters.error_test_failures, compiled.solver.counters.error_test_failures);
  EXPECT_EQ(own.solver.counters.jacobian_evaluations, compiled.solver.counters.jacobian_evaluations);
  EXPECT_EQ(own.solver.counters.nonlinear_iterations, compiled.solver.counters.nonlinear_iterations);
  EXPECT_TRUE(same_bits(own.metrics.peak_contact_force, compiled.metrics.peak_contact_force));
  EXPECT_TRUE(same_bits(own.metrics.min_contact_force, compiled.metrics.min_contact_force));
  ASSERT_EQ(own.series.time.size(), compiled.series.time.size());
  for (std::size_t i = 0; i < own.series.time.size(); ++i)
    ASSERT_TRUE(same_bits(own.series.follower_position[i], compiled.series.follower_position[i])) << i;
}

// The stiff undamped contact of issue 38 (bench/stiff_contact_bench.cc) for
// `cycles` revolutions at rtol 1e-10.
SceneConfig stiff_undamped_contact(double cycles) {
  SceneConfig scene = test::cycloidal_cam_scene(100.0, ContactModel::hertz);
  scene.integrator.rtol = 1e-10;
  scene.integrator.atol = 1e-12;
  scene.simulation.cycles = cycles;
  scene.simulation.discard_cycles = 0;
  return scene;
}

// A quarter revolution of the stiff contact: a dense 3-state solve.
TEST(CompiledKernels, StiffUndampedContactRunIsTheSameToTheBit) {
  const auto [own, compiled] = both_ways(stiff_undamped_contact(0.25));
  EXPECT_GT(own.solver.counters.error_test_failures, 0);
  expect_same_run(own, compiled);
}

// The same scene with ARKODE (the compiled kernels are installed in its
// vectors and its dense solver too): the order-8 explicit pair and the
// default implicit one, a sixteenth of a revolution.
TEST(CompiledKernels, ArkodeRunsAreTheSameToTheBit) {
  SceneConfig scene = stiff_undamped_contact(0.0625);
  scene.integrator.method = IntegrationMethod::arkode_erk;
  scene.integrator.order = 8;
  const auto erk = both_ways(scene);
  expect_same_run(erk.first, erk.second);
  scene.integrator.method = IntegrationMethod::arkode_dirk;
  scene.integrator.order.reset();
  const auto dirk = both_ways(scene);
  EXPECT_GT(dirk.first.solver.counters.jacobian_evaluations, 0);
  expect_same_run(dirk.first, dirk.second);
}

// A spring with mass in 8 coils on a seat: the banded solve.
TEST(CompiledKernels, EightCoilTrainRunIsTheSameToTheBit) {
  SceneConfig scene = test::cycloidal_cam_scene(1500.0, ContactModel::hunt_crossley);
  FollowerConfig& f = scene.mechanism.follower;
  f.spring.mass = 0.03;
  f.spring.coils = 8;
  SeatConfig seat;
  seat.position = 2e-5;
  seat.model = ContactModel::hunt_crossley;
  seat.stiffness = 1e9;
  f.seat = seat;
  scene.simulation.cycles = 0.5;
  scene.simulation.discard_cycles = 0;
  const auto [own, compiled] = both_ways(scene);
  expect_same_run(own, compiled);
}

}  // namespace
}  // namespace camdyn
