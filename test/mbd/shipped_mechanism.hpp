#pragma once
// The mechanism parameters of a shipped config (launch_free_configs/NAME), for the mbd tests.
#include <string>

#include "core/config.hpp"
#include "mbd/mechanism_params.hpp"

namespace test_mbd {

// The mbd tests exercise the mechanism with the equivalent bed: its calibrated configs by default.
inline mbd::MechanismParams shipped_mechanism(const std::string& name = "gyp1200_400rpm_bed.yaml") {
  const auto root = core::ConfigNode::load_file(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/" + name);
  return mbd::load_mechanism_params(root.child("mbd"));
}

}  // namespace test_mbd
