#pragma once
// The one-line-per-stage summaries porter-plan prints on stdout (README.md beside this file).

#include <string>

#include "backend_stage.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend_result.hpp"

namespace porter::app {

std::string frontend_summary(const frontend::FrontendResult& r);
std::string midend_summary(const midend::MidendResult& r);
std::string backend_summary(const BackendRun& run);

}  // namespace porter::app
