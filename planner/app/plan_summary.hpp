#pragma once
// The one-line-per-stage summaries porter-plan prints on stdout (README.md beside this file).

#include <string>

#include "porter/frontend/frontend.hpp"
#include "porter/pipeline/plan_result.hpp"

namespace porter::app {

std::string frontend_summary(const frontend::FrontendResult& r);
std::string midend_summary(const pipeline::MidendReport& m);
std::string backend_summary(const pipeline::BackendReport& run);

}  // namespace porter::app
