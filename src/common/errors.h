// The error types of the library's internals. They are the public ones
// (<camdyn/errors.h>: InputError, NumericalError), defined there so that a
// caller of the public API catches the very types the internals throw; this
// header keeps the internal include path ("common/errors.h") of every layer.
#pragma once

#include <camdyn/errors.h>
