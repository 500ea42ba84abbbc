// Counts calls to the global operator new, which allocation_counter.cc
// replaces in every executable that links it: the right-hand side and the
// curve evaluations it calls must not allocate (Pinocchio's
// EIGEN_RUNTIME_NO_MALLOC, extended to all heap use).
#pragma once

namespace camdyn::test {

/// Number of operator new calls in this process so far.
long allocation_count();

}  // namespace camdyn::test
