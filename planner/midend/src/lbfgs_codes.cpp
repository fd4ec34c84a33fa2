#include "porter/midend/lbfgs_codes.hpp"

#include <lbfgs.h>

namespace porter::midend {

const char* lbfgs_code_to_string(int code) {
  switch (code) {
    case LBFGS_SUCCESS: return "success (gradient test)";
    case LBFGS_STOP: return "stopped by the relative cost decrease test";
    case LBFGS_ALREADY_MINIMIZED: return "initial point already minimizes";
    case LBFGSERR_UNKNOWNERROR: return "unknown error";
    case LBFGSERR_LOGICERROR: return "logic error";
    case LBFGSERR_OUTOFMEMORY: return "out of memory";
    case LBFGSERR_CANCELED: return "canceled by the progress callback";
    case LBFGSERR_INVALID_N: return "invalid number of variables";
    case LBFGSERR_INVALID_N_SSE: return "invalid number of variables for SSE";
    case LBFGSERR_INVALID_X_SSE: return "variable array not aligned for SSE";
    case LBFGSERR_INVALID_EPSILON: return "invalid epsilon";
    case LBFGSERR_INVALID_TESTPERIOD: return "invalid past";
    case LBFGSERR_INVALID_DELTA: return "invalid delta";
    case LBFGSERR_INVALID_LINESEARCH: return "invalid line search";
    case LBFGSERR_INVALID_MINSTEP: return "invalid min_step";
    case LBFGSERR_INVALID_MAXSTEP: return "invalid max_step";
    case LBFGSERR_INVALID_FTOL: return "invalid ftol";
    case LBFGSERR_INVALID_WOLFE: return "invalid wolfe";
    case LBFGSERR_INVALID_GTOL: return "invalid gtol";
    case LBFGSERR_INVALID_XTOL: return "invalid xtol";
    case LBFGSERR_INVALID_MAXLINESEARCH: return "invalid max_linesearch";
    case LBFGSERR_INVALID_ORTHANTWISE: return "invalid orthantwise_c";
    case LBFGSERR_INVALID_ORTHANTWISE_START: return "invalid orthantwise_start";
    case LBFGSERR_INVALID_ORTHANTWISE_END: return "invalid orthantwise_end";
    case LBFGSERR_OUTOFINTERVAL: return "line search step out of the interval of uncertainty";
    case LBFGSERR_INCORRECT_TMINMAX: return "line search: interval of uncertainty violated";
    case LBFGSERR_ROUNDING_ERROR: return "line search: rounding error";
    case LBFGSERR_MINIMUMSTEP: return "line search: step below min_step";
    case LBFGSERR_MAXIMUMSTEP: return "line search: step above max_step";
    case LBFGSERR_MAXIMUMLINESEARCH: return "line search: evaluation cap reached";
    case LBFGSERR_MAXIMUMITERATION: return "iteration cap reached";
    case LBFGSERR_WIDTHTOOSMALL: return "line search: interval too small";
    case LBFGSERR_INVALIDPARAMETERS: return "invalid parameters (negative line-search step?)";
    case LBFGSERR_INCREASEGRADIENT: return "search direction increases the cost";
    default: return "unknown lbfgs code";
  }
}

bool lbfgs_code_is_stall(int code) {
  switch (code) {
    case LBFGSERR_OUTOFINTERVAL:
    case LBFGSERR_INCORRECT_TMINMAX:
    case LBFGSERR_ROUNDING_ERROR:
    case LBFGSERR_MINIMUMSTEP:
    case LBFGSERR_MAXIMUMSTEP:
    case LBFGSERR_MAXIMUMLINESEARCH:
    case LBFGSERR_WIDTHTOOSMALL:
    case LBFGSERR_INCREASEGRADIENT:
      return true;
    default:
      return false;
  }
}

}  // namespace porter::midend
