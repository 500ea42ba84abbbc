#include "integrate/arkode_integrator.h"

#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <string>

#include "common/errors.h"
#include "integrate/sundials_compiled_ops.h"
#include "integrate/sundials_flag_name.h"

namespace camdyn {

struct ArkodeIntegrator::Impl {
  explicit Impl(OdeSystem& ode) : system(ode) {}
  OdeSystem& system;
  bool implicit = false;
  SUNContext context = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr, scratch = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear_solver = nullptr;
  std::string last_message;
  SolverCounters before_reinit;
  double t = 0.0;

  void check(int flag, const char* call) const {
    if (flag >= 0) return;
    throw NumericalError(std::string("ARKODE ") + call + " failed (" + take_flag_name(ARKStepGetReturnFlagName(flag)) +
                         ") at t = " + std::to_string(t) + " s" +
                         (last_message.empty() ? std::string() : ": " + last_message));
  }
  void check_created(const void* p, const char* what) const {
    if (p == nullptr) throw NumericalError(std::string("SUNDIALS could not create ") + what);
  }

  static int rhs(realtype t, N_Vector y, N_Vector y_dot, void* data) {
    return static_cast<Impl*>(data)->system.rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(y_dot));
  }
  static int roots(realtype t, N_Vector y, realtype* g, void* data) {
    return static_cast<Impl*>(data)->system.roots(t, N_VGetArrayPointer(y), g);
  }
  static int jacobian(realtype t, N_Vector y, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector, N_Vector) {
    return static_cast<Impl*>(data)->system.jacobian(t, N_VGetArrayPointer(y), SUNDenseMatrix_Data(J));
  }
  static void error_handler(int, const char* module, const char* function, char* message, void* data) {
    static_cast<Impl*>(data)->last_message = std::string(module) + "/" + function + ": " + message;
  }

  SolverCounters current() const {
    SolverCounters c;
    long v = 0, fe = 0, fi = 0;
    check(ARKStepGetNumSteps(mem, &v), "ARKStepGetNumSteps");
    c.steps = v;
    check(ARKStepGetNumRhsEvals(mem, &fe, &fi), "ARKStepGetNumRhsEvals");
    c.rhs_evaluations = fe + fi;
    check(ARKStepGetNumErrTestFails(mem, &v), "ARKStepGetNumErrTestFails");
    c.error_test_failures = v;
    if (implicit) {
      check(ARKStepGetNumLinRhsEvals(mem, &v), "ARKStepGetNumLinRhsEvals");
      c.rhs_evaluations += v;
      check(ARKStepGetNumNonlinSolvIters(mem, &v), "ARKStepGetNumNonlinSolvIters");
      c.nonlinear_iterations = v;
      check(ARKStepGetNumJacEvals(mem, &v), "ARKStepGetNumJacEvals");
      c.jacobian_evaluations = v;
    }
    return c;
  }

  ~Impl() {
    if (mem) ARKStepFree(&mem);
    if (linear_solver) SUNLinSolFree(linear_solver);
    if (matrix) SUNMatDestroy(matrix);
    for (N_Vector v : {y, scratch})
      if (v) N_VDestroy(v);
    if (context) SUNContext_Free(&context);
  }
};

ArkodeIntegrator::ArkodeIntegrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0)
    : impl_(std::make_unique<Impl>(system)), t_(t0), t_prev_(t0) {
  Impl& m = *impl_;
  m.implicit = options.method == IntegrationMethod::arkode_dirk;
  m.t = t0;
  const sunindextype size = m.system.size();
  if (SUNContext_Create(nullptr, &m.context) != 0) throw NumericalError("SUNDIALS could not create a context");
  m.y = N_VNew_Serial(size, m.context);
  m.check_created(m.y, "the state vector");
  m.scratch = N_VNew_Serial(size, m.context);
  m.check_created(m.scratch, "a work vector");
  // Before ARKStepCreate, whose vectors are clones of y (sundials_compiled_ops.h).
  const bool compiled = compiled_kernels_enabled();
  if (compiled) {
    use_compiled_vector_ops(m.y);
    use_compiled_vector_ops(m.scratch);
  }
  for (sunindextype i = 0; i < size; ++i) NV_Ith_S(m.y, i) = y0[i];
  m.mem = m.implicit ? ARKStepCreate(nullptr, &Impl::rhs, t0, m.y, m.context)
                     : ARKStepCreate(&Impl::rhs, nullptr, t0, m.y, m.context);
  m.check_created(m.mem, "the ARKStep solver");
  m.check(ARKStepSetErrHandlerFn(m.mem, &Impl::error_handler, &m), "ARKStepSetErrHandlerFn");
  m.check(ARKStepSetUserData(m.mem, &m), "ARKStepSetUserData");
  m.check(ARKStepSStolerances(m.mem, options.rtol, options.atol), "ARKStepSStolerances");
  m.check(ARKStepSetMaxNumSteps(m.mem, options.max_steps_per_call), "ARKStepSetMaxNumSteps");
  if (options.max_step > 0.0) m.check(ARKStepSetMaxStep(m.mem, options.max_step), "ARKStepSetMaxStep");
  // ARKODE's default table of that order (integrator.order): a higher order
  // pays where accuracy, not stability, sets the step, as on an undamped
  // contact vibration followed at a tight tolerance (docs/performance.md
  // "A stiff undamped contact").
  if (options.order > 0) m.check(ARKStepSetOrder(m.mem, options.order), "ARKStepSetOrder");
  if (m.implicit) {
    m.matrix = SUNDenseMatrix(size, size, m.context);
    m.check_created(m.matrix, "the dense Jacobian matrix");
    m.linear_solver = SUNLinSol_Dense(m.y, m.matrix, m.context);
    m.check_created(m.linear_solver, "the dense linear solver");
    if (compiled) use_compiled_dense_solver(m.linear_solver);
    m.check(ARKStepSetLinearSolver(m.mem, m.linear_solver, m.matrix), "ARKStepSetLinearSolver");
    // The contact makes the implicit stages strongly nonlinear: the default
    // trivial predictor and 3 Newton iterations made the step collapse (10×
    // more steps than BDF on a 1e12 N/m^1.5 contact); the maximum-order
    // predictor and up to 10 iterations restore sensible steps.
    m.check(ARKStepSetPredictorMethod(m.mem, 1), "ARKStepSetPredictorMethod");
    m.check(ARKStepSetMaxNonlinIters(m.mem, 10), "ARKStepSetMaxNonlinIters");
    if (options.analytic_jacobian && m.system.has_jacobian())
      m.check(ARKStepSetJacFn(m.mem, &Impl::jacobian), "ARKStepSetJacFn");
  }
  if (m.system.root_count() > 0) {
    m.check(ARKStepRootInit(m.mem, m.system.root_count(), &Impl::roots), "ARKStepRootInit");
    m.check(ARKStepSetNoInactiveRootWarn(m.mem), "ARKStepSetNoInactiveRootWarn");
  }
}

ArkodeIntegrator::~ArkodeIntegrator() = default;

Integrator::Result ArkodeIntegrator::step(double t_stop) {
  Impl& m = *impl_;
  m.check(ARKStepSetStopTime(m.mem, t_stop), "ARKStepSetStopTime");
  double t_reached = t_;
  const int flag = ARKStepEvolve(m.mem, t_stop, m.y, &t_reached, ARK_ONE_STEP);
  m.t = t_reached;
  m.check(flag, "ARKStepEvolve");
  double h_last = 0.0, t_current = t_reached;
  m.check(ARKStepGetLastStep(m.mem, &h_last), "ARKStepGetLastStep");
  m.check(ARKStepGetCurrentTime(m.mem, &t_current), "ARKStepGetCurrentTime");
  t_prev_ = std::max(t_, t_current - h_last);
  t_ = t_reached;
  if (flag == ARK_ROOT_RETURN) return Result::root;
  if (flag == ARK_TSTOP_RETURN) return Result::stop;
  return Result::step;
}

const double* ArkodeIntegrator::state() const { return N_VGetArrayPointer(impl_->y); }

void ArkodeIntegrator::dense(double t, double* out) const {
  Impl& m = *impl_;
  m.check(ARKStepGetDky(m.mem, t, 0, m.scratch), "ARKStepGetDky");
  const double* p = N_VGetArrayPointer(m.scratch);
  std::copy(p, p + m.system.size(), out);
}

void ArkodeIntegrator::root_info(int* directions) const {
  impl_->check(ARKStepGetRootInfo(impl_->mem, directions), "ARKStepGetRootInfo");
}

void ArkodeIntegrator::reinit(double t, const double* y) {
  Impl& m = *impl_;
  m.before_reinit += m.current();
  ++m.before_reinit.reinitialisations;
  for (int i = 0; i < m.system.size(); ++i) NV_Ith_S(m.y, i) = y[i];
  m.t = t;
  m.check(m.implicit ? ARKStepReInit(m.mem, nullptr, &Impl::rhs, t, m.y)
                     : ARKStepReInit(m.mem, &Impl::rhs, nullptr, t, m.y),
          "ARKStepReInit");
  t_ = t_prev_ = t;
}

SolverCounters ArkodeIntegrator::counters() const {
  SolverCounters c = impl_->current();
  c += impl_->before_reinit;
  return c;
}

long ArkodeIntegrator::steps() const {
  long v = 0;
  impl_->check(ARKStepGetNumSteps(impl_->mem, &v), "ARKStepGetNumSteps");
  return v + impl_->before_reinit.steps;
}

}  // namespace camdyn
