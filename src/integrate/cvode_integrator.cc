#include "integrate/cvode_integrator.h"

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "common/errors.h"
#include "integrate/sundials_compiled_ops.h"
#include "integrate/sundials_flag_name.h"

namespace camdyn {

struct CvodeIntegrator::Impl {
  OdeSystem* system = nullptr;
  SUNContext context = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr, scratch = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear_solver = nullptr;
  int band = -1;              // half-bandwidth of a banded Jacobian; −1: dense
  std::vector<double> dense;  // banded: the system's Jacobian, column-major n × n, before it is banded
  std::string last_message;
  SolverCounters before_reinit;  // counters of earlier integrations (CVodeReInit resets them)
  double t = 0.0;
  // Forward sensitivities (enable_sensitivities): the vectors CVODES reads
  // and writes, and the column pointers handed to the system (made once, so
  // that the sensitivity right-hand side allocates nothing).
  int sensitivity_count = 0;
  N_Vector* sensitivity = nullptr;
  std::vector<const double*> s_columns;
  std::vector<double*> s_dot_columns;

  void check(int flag, const char* call) const {
    if (flag >= 0) return;
    throw NumericalError(std::string("CVODES ") + call + " failed (" + take_flag_name(CVodeGetReturnFlagName(flag)) +
                         ") at t = " + std::to_string(t) + " s" +
                         (last_message.empty() ? std::string() : ": " + last_message));
  }
  void check_created(const void* p, const char* what) const {
    if (p == nullptr) throw NumericalError(std::string("SUNDIALS could not create ") + what);
  }

  static int rhs(realtype t, N_Vector y, N_Vector y_dot, void* data) {
    return static_cast<Impl*>(data)->system->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(y_dot));
  }
  static int sensitivity_rhs(int count, realtype t, N_Vector y, N_Vector, N_Vector* s, N_Vector* s_dot, void* data,
                             N_Vector, N_Vector) {
    Impl& m = *static_cast<Impl*>(data);
    for (int j = 0; j < count; ++j) {
      m.s_columns[static_cast<std::size_t>(j)] = N_VGetArrayPointer(s[j]);
      m.s_dot_columns[static_cast<std::size_t>(j)] = N_VGetArrayPointer(s_dot[j]);
    }
    return m.system->sensitivity_rhs(t, N_VGetArrayPointer(y), count, m.s_columns.data(), m.s_dot_columns.data());
  }
  static int roots(realtype t, N_Vector y, realtype* g, void* data) {
    return static_cast<Impl*>(data)->system->roots(t, N_VGetArrayPointer(y), g);
  }
  static int jacobian(realtype t, N_Vector y, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector, N_Vector) {
    Impl& m = *static_cast<Impl*>(data);
    if (m.band < 0) return m.system->jacobian(t, N_VGetArrayPointer(y), SUNDenseMatrix_Data(J));
    const int flag = m.system->jacobian(t, N_VGetArrayPointer(y), m.dense.data());
    if (flag != 0) return flag;
    const sunindextype n = SUNBandMatrix_Columns(J);
    for (sunindextype j = 0; j < n; ++j)
      for (sunindextype i = std::max<sunindextype>(0, j - m.band); i <= std::min<sunindextype>(n - 1, j + m.band); ++i)
        SM_ELEMENT_B(J, i, j) = m.dense[static_cast<std::size_t>(i + n * j)];
    return 0;
  }
  static void error_handler(int, const char* module, const char* function, char* message, void* data) {
    static_cast<Impl*>(data)->last_message = std::string(module) + "/" + function + ": " + message;
  }

  SolverCounters current() const {
    SolverCounters c;
    long v = 0;
    check(CVodeGetNumSteps(mem, &v), "CVodeGetNumSteps");
    c.steps = v;
    check(CVodeGetNumRhsEvals(mem, &v), "CVodeGetNumRhsEvals");
    c.rhs_evaluations = v;
    check(CVodeGetNumLinRhsEvals(mem, &v), "CVodeGetNumLinRhsEvals");
    c.rhs_evaluations += v;
    check(CVodeGetNumErrTestFails(mem, &v), "CVodeGetNumErrTestFails");
    c.error_test_failures = v;
    check(CVodeGetNumNonlinSolvIters(mem, &v), "CVodeGetNumNonlinSolvIters");
    c.nonlinear_iterations = v;
    check(CVodeGetNumJacEvals(mem, &v), "CVodeGetNumJacEvals");
    c.jacobian_evaluations = v;
    return c;
  }

  ~Impl() {
    if (mem) CVodeFree(&mem);
    if (sensitivity) N_VDestroyVectorArray(sensitivity, sensitivity_count);
    if (linear_solver) SUNLinSolFree(linear_solver);
    if (matrix) SUNMatDestroy(matrix);
    for (N_Vector v : {y, scratch})
      if (v) N_VDestroy(v);
    if (context) SUNContext_Free(&context);
  }
};

CvodeIntegrator::CvodeIntegrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0)
    : impl_(std::make_unique<Impl>()), t_(t0), t_prev_(t0) {
  Impl& m = *impl_;
  m.system = &system;
  m.t = t0;
  const sunindextype n = system.size();
  if (SUNContext_Create(nullptr, &m.context) != 0) throw NumericalError("SUNDIALS could not create a context");
  m.y = N_VNew_Serial(n, m.context);
  m.check_created(m.y, "the state vector");
  m.scratch = N_VNew_Serial(n, m.context);
  m.check_created(m.scratch, "a work vector");
  // Before CVodeInit, whose vectors are clones of y (sundials_compiled_ops.h).
  const bool compiled = compiled_kernels_enabled();
  if (compiled) {
    use_compiled_vector_ops(m.y);
    use_compiled_vector_ops(m.scratch);
  }
  for (sunindextype i = 0; i < n; ++i) NV_Ith_S(m.y, i) = y0[i];
  m.mem = CVodeCreate(options.method == IntegrationMethod::cvode_adams ? CV_ADAMS : CV_BDF, m.context);
  m.check_created(m.mem, "the CVODES solver");
  m.check(CVodeSetErrHandlerFn(m.mem, &Impl::error_handler, &m), "CVodeSetErrHandlerFn");
  m.check(CVodeInit(m.mem, &Impl::rhs, t0, m.y), "CVodeInit");
  m.check(CVodeSetUserData(m.mem, &m), "CVodeSetUserData");
  m.check(CVodeSStolerances(m.mem, options.rtol, options.atol), "CVodeSStolerances");
  m.check(CVodeSetMaxNumSteps(m.mem, options.max_steps_per_call), "CVodeSetMaxNumSteps");
  if (options.max_step > 0.0) m.check(CVodeSetMaxStep(m.mem, options.max_step), "CVodeSetMaxStep");
  // The contact adds a lightly damped, fast oscillatory mode: BDF of order
  // 3-5 is not stable near the imaginary axis, and stability-limit detection
  // lowers the order instead of shrinking the step.
  if (options.method != IntegrationMethod::cvode_adams)
    m.check(CVodeSetStabLimDet(m.mem, SUNTRUE), "CVodeSetStabLimDet");
  m.band = system.bandwidth();
  if (m.band >= 0) {
    // A chain of lumped masses: banded LU, linear in its length.
    m.matrix = SUNBandMatrix(n, m.band, m.band, m.context);
    m.check_created(m.matrix, "the banded Jacobian matrix");
    m.linear_solver = SUNLinSol_Band(m.y, m.matrix, m.context);
    m.check_created(m.linear_solver, "the banded linear solver");
    if (compiled) use_compiled_band_solver(m.linear_solver);
    m.dense.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  } else {
    m.matrix = SUNDenseMatrix(n, n, m.context);
    m.check_created(m.matrix, "the dense Jacobian matrix");
    m.linear_solver = SUNLinSol_Dense(m.y, m.matrix, m.context);
    m.check_created(m.linear_solver, "the dense linear solver");
    if (compiled) use_compiled_dense_solver(m.linear_solver);
  }
  m.check(CVodeSetLinearSolver(m.mem, m.linear_solver, m.matrix), "CVodeSetLinearSolver");
  if (options.analytic_jacobian && system.has_jacobian())
    m.check(CVodeSetJacFn(m.mem, &Impl::jacobian), "CVodeSetJacFn");
  if (system.root_count() > 0) {
    m.check(CVodeRootInit(m.mem, system.root_count(), &Impl::roots), "CVodeRootInit");
    m.check(CVodeSetNoInactiveRootWarn(m.mem), "CVodeSetNoInactiveRootWarn");
  }
}

CvodeIntegrator::~CvodeIntegrator() = default;

CvodeIntegrator::Result CvodeIntegrator::step(double t_stop) {
  Impl& m = *impl_;
  m.check(CVodeSetStopTime(m.mem, t_stop), "CVodeSetStopTime");
  double t_reached = t_;
  const int flag = CVode(m.mem, t_stop, m.y, &t_reached, CV_ONE_STEP);
  m.t = t_reached;
  m.check(flag, "CVode");
  double h_last = 0.0;
  m.check(CVodeGetLastStep(m.mem, &h_last), "CVodeGetLastStep");
  double t_current = t_reached;
  m.check(CVodeGetCurrentTime(m.mem, &t_current), "CVodeGetCurrentTime");
  // Dense output is valid over the last internal step [t_current − h, t_current];
  // after a root the returned time lies inside it.
  t_prev_ = std::max(t_, t_current - h_last);
  t_ = t_reached;
  if (flag == CV_ROOT_RETURN) return Result::root;
  if (flag == CV_TSTOP_RETURN) return Result::stop;
  return Result::step;
}

const double* CvodeIntegrator::state() const { return N_VGetArrayPointer(impl_->y); }

void CvodeIntegrator::dense(double t, double* out) const {
  Impl& m = *impl_;
  m.check(CVodeGetDky(m.mem, t, 0, m.scratch), "CVodeGetDky");
  const double* p = N_VGetArrayPointer(m.scratch);
  for (int i = 0; i < m.system->size(); ++i) out[i] = p[i];
}

void CvodeIntegrator::root_info(int* directions) const {
  impl_->check(CVodeGetRootInfo(impl_->mem, directions), "CVodeGetRootInfo");
}

void CvodeIntegrator::reinit(double t, const double* y) {
  Impl& m = *impl_;
  m.before_reinit += m.current();
  ++m.before_reinit.reinitialisations;
  for (int i = 0; i < m.system->size(); ++i) NV_Ith_S(m.y, i) = y[i];
  m.t = t;
  m.check(CVodeReInit(m.mem, t, m.y), "CVodeReInit");
  t_ = t_prev_ = t;
}

void CvodeIntegrator::enable_sensitivities(int count, const double* s0) {
  Impl& m = *impl_;
  if (m.sensitivity) throw std::logic_error("CvodeIntegrator::enable_sensitivities called twice");
  const int n = m.system->size();
  m.sensitivity = N_VCloneVectorArray(count, m.y);
  m.check_created(m.sensitivity, "the sensitivity vectors");
  m.sensitivity_count = count;
  m.s_columns.assign(static_cast<std::size_t>(count), nullptr);
  m.s_dot_columns.assign(static_cast<std::size_t>(count), nullptr);
  for (int j = 0; j < count; ++j)
    std::copy(s0 + static_cast<std::ptrdiff_t>(n) * j, s0 + static_cast<std::ptrdiff_t>(n) * (j + 1),
              N_VGetArrayPointer(m.sensitivity[j]));
  m.check(CVodeSensInit(m.mem, count, CV_STAGGERED, &Impl::sensitivity_rhs, m.sensitivity), "CVodeSensInit");
  m.check(CVodeSensEEtolerances(m.mem), "CVodeSensEEtolerances");
  m.check(CVodeSetSensErrCon(m.mem, SUNTRUE), "CVodeSetSensErrCon");
}

void CvodeIntegrator::sensitivities(double* s) const {
  Impl& m = *impl_;
  double t_reached = t_;
  m.check(CVodeGetSens(m.mem, &t_reached, m.sensitivity), "CVodeGetSens");
  const int n = m.system->size();
  for (int j = 0; j < m.sensitivity_count; ++j) {
    const double* column = N_VGetArrayPointer(m.sensitivity[j]);
    std::copy(column, column + n, s + static_cast<std::ptrdiff_t>(n) * j);
  }
}

void CvodeIntegrator::reinit(double t, const double* y, const double* s) {
  reinit(t, y);
  Impl& m = *impl_;
  const int n = m.system->size();
  for (int j = 0; j < m.sensitivity_count; ++j)
    std::copy(s + static_cast<std::ptrdiff_t>(n) * j, s + static_cast<std::ptrdiff_t>(n) * (j + 1),
              N_VGetArrayPointer(m.sensitivity[j]));
  m.check(CVodeSensReInit(m.mem, CV_STAGGERED, m.sensitivity), "CVodeSensReInit");
}

SolverCounters CvodeIntegrator::counters() const {
  SolverCounters c = impl_->current();
  c += impl_->before_reinit;
  return c;
}

long CvodeIntegrator::steps() const {
  long v = 0;
  impl_->check(CVodeGetNumSteps(impl_->mem, &v), "CVodeGetNumSteps");
  return v + impl_->before_reinit.steps;
}

}  // namespace camdyn
