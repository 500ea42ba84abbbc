// The InputError a piece of code throws, for tests that check its file,
// dotted path and reason.
#pragma once

#include <gtest/gtest.h>

#include "common/errors.h"

namespace camdyn::test {

/// The InputError that `f` throws (fails the test when it throws none).
template <class F>
InputError input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", "", "");
}

}  // namespace camdyn::test
