#pragma once
// PlannerSettings from the config/planner/*.yaml files (porter::pipeline_io; the pipeline library
// itself reads no YAML):
//   pipeline.yaml   budgets, collision / safety models, mid-end retry, goal defaults, kernel and
//                   sphere checkers (PipelineSettings, KernelCheckerSettings, SphereCheckerSettings)
//   frontend.yaml   frontend::FrontendSettings and its sub-stages
//   midend.yaml     midend::MidendSettings
//   backend.yaml    backend::BackendSettings and the back-end's terms
// Strict: every key is required, an unknown key, a wrong type or an out-of-range value is a
// LoadError naming the file and the key ("config/planner/midend.yaml: key
// 'solver.memory_size': must be in [3, 64], got 2"); a combination the stages refuse names the
// file and the field. The shipped files hold the defaults (the structs' in-class values).

#include <string>

#include "porter/pipeline/planner_settings.hpp"

namespace porter::pipeline {

/// Loads the four files from `dir` (config/planner). Throws LoadError.
PlannerSettings load_planner_settings(const std::string& dir);

/// One file each, into `settings` (the other fields are kept). Throw LoadError.
void load_pipeline_yaml(const std::string& file, PlannerSettings& settings);
void load_frontend_yaml(const std::string& file, frontend::FrontendSettings& settings);
void load_midend_yaml(const std::string& file, midend::MidendSettings& settings);
void load_backend_yaml(const std::string& file, PlannerSettings& settings);

}  // namespace porter::pipeline
