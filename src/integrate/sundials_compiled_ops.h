// camdyn's own, optimised implementations of the SUNDIALS kernels a CVODES or
// ARKODE step spends its time in, installed through SUNDIALS' operation tables:
// the serial N_Vector's element-wise operations and norms, and the banded and
// dense LU factorisations and solves. The installed SUNDIALS 6.4.1 (Debian's package) is
// built without optimisation, so on a short state (a follower train of 10–40
// states) these kernels cost more than the model's right-hand side
// (docs/performance.md). Each does the same arithmetic in the same order
// as SUNDIALS' own (nvector_serial.c, sundials_band.c, sundials_dense.c), so that a run's
// answer is the same to the bit; only the compiler's optimisation differs.
#pragma once

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_nvector.h>

namespace camdyn {

/// Whether CVODES and ARKODE integrators created from now on use the compiled kernels
/// (the default), process-wide. Off only to measure or check them against
/// SUNDIALS' own (bench/stiff_contact_bench.cc, tests/integrate).
bool compiled_kernels_enabled();
void set_compiled_kernels_enabled(bool on);

/// Points a serial N_Vector's element-wise operations (linear sum, scale,
/// const, product, quotient, absolute value, inverse, add constant, weighted
/// RMS and max norms, minimum) at camdyn's implementations. Vectors cloned from it
/// afterwards (CVodeInit, ARKStepCreate, the linear solver) inherit them.
void use_compiled_vector_ops(N_Vector v);

/// Points a SUNLinSol_Band solver's setup (LU factorisation) and solve at
/// the compiled copies of SUNDlsMat_bandGBTRF / bandGBTRS.
void use_compiled_band_solver(SUNLinearSolver solver);

/// Points a SUNLinSol_Dense solver's setup and solve at camdyn's implementations
/// of SUNDlsMat_denseGETRF / denseGETRS.
void use_compiled_dense_solver(SUNLinearSolver solver);

}  // namespace camdyn
