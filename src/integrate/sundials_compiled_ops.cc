#include "integrate/sundials_compiled_ops.h"

#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace camdyn {

namespace {

// The serial vector kernels, case for case as N_VLinearSum_Serial & co. pick
// them (SUNDIALS 6.4.1 nvector_serial.c), each a plain loop over the data.

struct Data {
  sunindextype n;
  realtype* p;
};
Data data(N_Vector v) { return {NV_LENGTH_S(v), NV_DATA_S(v)}; }

/// y ← a x + y
void axpy(realtype a, N_Vector x, N_Vector y) {
  const auto [n, xd] = data(x);
  realtype* yd = NV_DATA_S(y);
  if (a == 1.0) {
    for (sunindextype i = 0; i < n; ++i) yd[i] += xd[i];
  } else if (a == -1.0) {
    for (sunindextype i = 0; i < n; ++i) yd[i] -= xd[i];
  } else {
    for (sunindextype i = 0; i < n; ++i) yd[i] += a * xd[i];
  }
}

void linear_sum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  if (b == 1.0 && z == y) return axpy(a, x, y);
  if (a == 1.0 && z == x) return axpy(b, y, x);
  const auto [n, zd] = data(z);
  const realtype *xd = NV_DATA_S(x), *yd = NV_DATA_S(y);
  if (a == 1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + yd[i];
  } else if (a == 1.0 && b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] - yd[i];
  } else if (a == -1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = yd[i] - xd[i];
  } else if (a == 1.0) {  // z = b y + x
    for (sunindextype i = 0; i < n; ++i) zd[i] = (b * yd[i]) + xd[i];
  } else if (b == 1.0) {  // z = a x + y
    for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + yd[i];
  } else if (a == -1.0) {  // z = b y − x
    for (sunindextype i = 0; i < n; ++i) zd[i] = (b * yd[i]) - xd[i];
  } else if (b == -1.0) {  // z = a x − y
    for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) - yd[i];
  } else if (a == b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
  } else if (a == -b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
  } else {
    for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + (b * yd[i]);
  }
}

void constant(realtype c, N_Vector z) {
  const auto [n, zd] = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = c;
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  const auto [n, zd] = data(z);
  const realtype *xd = NV_DATA_S(x), *yd = NV_DATA_S(y);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] * yd[i];
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  const auto [n, zd] = data(z);
  const realtype *xd = NV_DATA_S(x), *yd = NV_DATA_S(y);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] / yd[i];
}

void scale(realtype c, N_Vector x, N_Vector z) {
  const auto [n, xd] = data(x);
  realtype* zd = NV_DATA_S(z);
  if (z == x) {
    for (sunindextype i = 0; i < n; ++i) xd[i] *= c;
  } else if (c == 1.0) {
    std::copy(xd, xd + n, zd);
  } else if (c == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = -xd[i];
  } else {
    for (sunindextype i = 0; i < n; ++i) zd[i] = c * xd[i];
  }
}

void absolute(N_Vector x, N_Vector z) {
  const auto [n, zd] = data(z);
  const realtype* xd = NV_DATA_S(x);
  for (sunindextype i = 0; i < n; ++i) zd[i] = std::fabs(xd[i]);
}

void inverse(N_Vector x, N_Vector z) {
  const auto [n, zd] = data(z);
  const realtype* xd = NV_DATA_S(x);
  for (sunindextype i = 0; i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_constant(N_Vector x, realtype b, N_Vector z) {
  const auto [n, zd] = data(z);
  const realtype* xd = NV_DATA_S(x);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + b;
}

realtype weighted_square_sum(N_Vector x, N_Vector w) {
  const auto [n, xd] = data(x);
  const realtype* wd = NV_DATA_S(w);
  realtype sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    const realtype p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

realtype weighted_rms_norm(N_Vector x, N_Vector w) {
  const realtype mean = weighted_square_sum(x, w) / static_cast<realtype>(NV_LENGTH_S(x));
  return mean <= 0.0 ? 0.0 : std::sqrt(mean);
}

realtype max_norm(N_Vector x) {
  const auto [n, xd] = data(x);
  realtype largest = 0.0;
  for (sunindextype i = 0; i < n; ++i)
    if (std::fabs(xd[i]) > largest) largest = std::fabs(xd[i]);
  return largest;
}

realtype minimum(N_Vector x) {
  const auto [n, xd] = data(x);
  realtype least = xd[0];
  for (sunindextype i = 1; i < n; ++i)
    if (xd[i] < least) least = xd[i];
  return least;
}

// The banded LU with partial pivoting and its solve, as SUNDlsMat_bandGBTRF /
// bandGBTRS (SUNDIALS 6.4.1 sundials_band.c): column k of the n × n matrix
// is a[k], its diagonal at a[k][smu], row i at a[k][i − k + smu].

sunindextype band_factor(realtype** a, sunindextype n, sunindextype mu, sunindextype ml, sunindextype smu,
                         sunindextype* p) {
  for (sunindextype c = 0; c < n; ++c) std::fill(a[c], a[c] + (smu - mu), 0.0);
  for (sunindextype k = 0; k < n - 1; ++k) {
    realtype* diag = a[k] + smu;
    const sunindextype last_row = std::min(n - 1, k + ml);
    sunindextype l = k;
    realtype largest = std::fabs(*diag);
    for (sunindextype i = k + 1; i <= last_row; ++i)
      if (std::fabs(diag[i - k]) > largest) {
        l = i;
        largest = std::fabs(diag[i - k]);
      }
    p[k] = l;
    if (diag[l - k] == 0.0) return k + 1;
    const bool swap = l != k;
    if (swap) std::swap(diag[l - k], *diag);
    const realtype mult = -1.0 / *diag;
    for (sunindextype i = k + 1; i <= last_row; ++i) diag[i - k] *= mult;
    const sunindextype last_col = std::min(k + smu, n - 1);
    for (sunindextype j = k + 1; j <= last_col; ++j) {
      realtype* col = a[j] + smu;  // col[i − j] is row i of column j
      const realtype a_kj = col[l - j];
      if (swap) {
        col[l - j] = col[k - j];
        col[k - j] = a_kj;
      }
      if (a_kj != 0.0)
        for (sunindextype i = k + 1; i <= last_row; ++i) col[i - j] += a_kj * diag[i - k];
    }
  }
  p[n - 1] = n - 1;
  return a[n - 1][smu] == 0.0 ? n : 0;
}

void band_solve(realtype** a, sunindextype n, sunindextype smu, sunindextype ml, const sunindextype* p, realtype* b) {
  for (sunindextype k = 0; k < n - 1; ++k) {
    const sunindextype l = p[k];
    const realtype mult = b[l];
    if (l != k) {
      b[l] = b[k];
      b[k] = mult;
    }
    const realtype* diag = a[k] + smu;
    const sunindextype last_row = std::min(n - 1, k + ml);
    for (sunindextype i = k + 1; i <= last_row; ++i) b[i] += mult * diag[i - k];
  }
  for (sunindextype k = n - 1; k >= 0; --k) {
    const realtype* diag = a[k] + smu;
    const sunindextype first_row = std::max<sunindextype>(0, k - smu);
    b[k] /= *diag;
    const realtype mult = -b[k];
    for (sunindextype i = first_row; i <= k - 1; ++i) b[i] += mult * diag[i - k];
  }
}

SUNLinearSolverContent_Band band_content(SUNLinearSolver s) {
  return static_cast<SUNLinearSolverContent_Band>(s->content);
}

// SUNLinSolSetup_Band / SUNLinSolSolve_Band with the kernels above.
int band_setup(SUNLinearSolver s, SUNMatrix A) {
  SUNLinearSolverContent_Band c = band_content(s);
  if (A == nullptr || SUNMatGetID(A) != SUNMATRIX_BAND) {
    c->last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  const sunindextype n = SM_COLUMNS_B(A), mu = SM_UBAND_B(A), ml = SM_LBAND_B(A), smu = SM_SUBAND_B(A);
  if (smu < std::min(n - 1, mu + ml)) {
    c->last_flag = SUNLS_MEM_FAIL;
    return SUNLS_MEM_FAIL;
  }
  c->last_flag = band_factor(SM_COLS_B(A), n, mu, ml, smu, c->pivots);
  return c->last_flag > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}

int band_solve_op(SUNLinearSolver s, SUNMatrix A, N_Vector x, N_Vector b, realtype /*tol*/) {
  SUNLinearSolverContent_Band c = band_content(s);
  scale(1.0, b, x);
  band_solve(SM_COLS_B(A), SM_COLUMNS_B(A), SM_SUBAND_B(A), SM_LBAND_B(A), c->pivots, NV_DATA_S(x));
  c->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

// The dense LU with partial pivoting and its solve, as SUNDlsMat_denseGETRF /
// denseGETRS (sundials_dense.c): column k of the m × n matrix is a[k].

sunindextype dense_factor(realtype** a, sunindextype m, sunindextype n, sunindextype* p) {
  for (sunindextype k = 0; k < n; ++k) {
    realtype* col_k = a[k];
    sunindextype l = k;
    for (sunindextype i = k + 1; i < m; ++i)
      if (std::fabs(col_k[i]) > std::fabs(col_k[l])) l = i;
    p[k] = l;
    if (col_k[l] == 0.0) return k + 1;
    if (l != k)
      for (sunindextype i = 0; i < n; ++i) std::swap(a[i][l], a[i][k]);
    const realtype mult = 1.0 / col_k[k];
    for (sunindextype i = k + 1; i < m; ++i) col_k[i] *= mult;
    for (sunindextype j = k + 1; j < n; ++j) {
      realtype* col_j = a[j];
      const realtype a_kj = col_j[k];
      if (a_kj != 0.0)
        for (sunindextype i = k + 1; i < m; ++i) col_j[i] -= a_kj * col_k[i];
    }
  }
  return 0;
}

void dense_solve(realtype** a, sunindextype n, const sunindextype* p, realtype* b) {
  for (sunindextype k = 0; k < n; ++k)
    if (p[k] != k) std::swap(b[k], b[p[k]]);
  for (sunindextype k = 0; k < n - 1; ++k) {
    const realtype* col_k = a[k];
    for (sunindextype i = k + 1; i < n; ++i) b[i] -= col_k[i] * b[k];
  }
  for (sunindextype k = n - 1; k > 0; --k) {
    const realtype* col_k = a[k];
    b[k] /= col_k[k];
    for (sunindextype i = 0; i < k; ++i) b[i] -= col_k[i] * b[k];
  }
  b[0] /= a[0][0];
}

SUNLinearSolverContent_Dense dense_content(SUNLinearSolver s) {
  return static_cast<SUNLinearSolverContent_Dense>(s->content);
}

// SUNLinSolSetup_Dense / SUNLinSolSolve_Dense with the kernels above.
int dense_setup(SUNLinearSolver s, SUNMatrix A) {
  SUNLinearSolverContent_Dense c = dense_content(s);
  if (A == nullptr || SUNMatGetID(A) != SUNMATRIX_DENSE) {
    c->last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  c->last_flag = dense_factor(SM_COLS_D(A), SM_ROWS_D(A), SM_COLUMNS_D(A), c->pivots);
  return c->last_flag > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}

int dense_solve_op(SUNLinearSolver s, SUNMatrix A, N_Vector x, N_Vector b, realtype /*tol*/) {
  SUNLinearSolverContent_Dense c = dense_content(s);
  scale(1.0, b, x);
  dense_solve(SM_COLS_D(A), SM_COLUMNS_D(A), c->pivots, NV_DATA_S(x));
  c->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

std::atomic<bool> compiled_kernels{true};

}  // namespace

bool compiled_kernels_enabled() { return compiled_kernels.load(std::memory_order_relaxed); }

void set_compiled_kernels_enabled(bool on) { compiled_kernels.store(on, std::memory_order_relaxed); }

void use_compiled_vector_ops(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = &linear_sum;
  ops->nvconst = &constant;
  ops->nvprod = &product;
  ops->nvdiv = &quotient;
  ops->nvscale = &scale;
  ops->nvabs = &absolute;
  ops->nvinv = &inverse;
  ops->nvaddconst = &add_constant;
  ops->nvmaxnorm = &max_norm;
  ops->nvwrmsnorm = &weighted_rms_norm;
  ops->nvmin = &minimum;
  ops->nvwsqrsumlocal = &weighted_square_sum;
  ops->nvmaxnormlocal = &max_norm;
  ops->nvminlocal = &minimum;
}

void use_compiled_band_solver(SUNLinearSolver solver) {
  solver->ops->setup = &band_setup;
  solver->ops->solve = &band_solve_op;
}

void use_compiled_dense_solver(SUNLinearSolver solver) {
  solver->ops->setup = &dense_setup;
  solver->ops->solve = &dense_solve_op;
}

}  // namespace camdyn
