#pragma once
// Where a process finds Porter's config directory (robots/, planner/, ...) when its command line
// does not name the files (porter::pipeline_io): no path of the build machine is compiled in.
//   1. ./config, relative to the working directory (scripts run from the repository root);
//   2. otherwise, walking up from the executable's directory: the first ancestor A with
//      A/config (a build tree inside the source tree: build/planner/app/porter-plan finds the
//      repository's config/) or A/share/porter/config (an installed tree).
// A directory counts when it holds planner/pipeline.yaml. Never throws.

#include <string>

namespace porter::pipeline {

/// The config directory, or "" when none is found.
std::string find_config_dir();

}  // namespace porter::pipeline
