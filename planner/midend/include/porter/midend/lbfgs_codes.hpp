#pragma once
// Names for liblbfgs return codes (lbfgs.h's LBFGS_* / LBFGSERR_* values), for messages and
// logs. Pure, thread-safe.

namespace porter::midend {

/// A short human-readable description of an lbfgs() return code; "unknown lbfgs code" for
/// values the library does not define.
const char* lbfgs_code_to_string(int code);

/// True for the codes that mean "the line search could not make further progress" (rounding
/// error, step limits, interval too small, line-search evaluation cap): the previous iterate
/// is still valid and may be accepted as converged-with-warning when the cost has decreased.
bool lbfgs_code_is_stall(int code);

}  // namespace porter::midend
