#pragma once
// porter-state's config file (config/state/porter_state.yaml) turned into parameters. Strict:
// every key is required; unknown keys and out-of-range values are LoadErrors naming the file
// and the key.
//
// Thread-safety: reentrant. Failure: throws porter::LoadError.

#include <string>

#include "porter/state/fusion.hpp"

namespace porter::state_app {

struct StateConfig {
  std::string file;
  state::FusionParams fusion;
  std::string frame_id = "world";        ///< frame of ROBOT_STATE; LIO_POSE must be in it
  std::string lio_child_frame_id = "base";  ///< LIO_POSE must be the pose of this frame
  double rate_hz = 100.0;                ///< ROBOT_STATE rate, Hz
};

StateConfig load_state_config(const std::string& path);

}  // namespace porter::state_app
