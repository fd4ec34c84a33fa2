#pragma once
// liblbfgs plumbing shared by every MINCO optimizer (mid-end, back-end): the parameter block
// built from a settings struct, the line-search mapping, and an owned solver buffer.
// Thread-safe: no shared state.

#include <lbfgs.h>

#include "porter/midend/midend_settings.hpp"

namespace porter::midend {

/// liblbfgs's constant for our line-search choice.
int to_lbfgs_line_search(LineSearch ls);

/// lbfgs_parameter_t for a settings struct with the mid-end's solver fields (memory_size,
/// relative_cost_past, relative_cost_tolerance, max_iterations, line_search, max_line_search).
/// The gradient-norm test is off: both stages stop on relative cost decrease only, because
/// their penalties are nonsmooth.
template <class Settings>
lbfgs_parameter_t lbfgs_parameters(const Settings& s) {
  lbfgs_parameter_t param;
  lbfgs_parameter_init(&param);
  param.m = s.memory_size;
  param.epsilon = 0.0;
  param.past = s.relative_cost_past;
  param.delta = s.relative_cost_tolerance;
  param.max_iterations = s.max_iterations;
  param.linesearch = to_lbfgs_line_search(s.line_search);
  param.max_linesearch = s.max_line_search;
  return param;
}

/// Owns an lbfgs_malloc'd array; data is null when the allocation failed.
struct LbfgsBuffer {
  explicit LbfgsBuffer(int n) : data(lbfgs_malloc(n)) {}
  ~LbfgsBuffer() { lbfgs_free(data); }
  LbfgsBuffer(const LbfgsBuffer&) = delete;
  LbfgsBuffer& operator=(const LbfgsBuffer&) = delete;
  lbfgsfloatval_t* data;
};

}  // namespace porter::midend
