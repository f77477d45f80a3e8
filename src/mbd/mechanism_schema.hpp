#pragma once
// The keys of the `mbd:` section (core/config_schema.hpp): load_mechanism_params reads through them and to_yaml
// (the checkpoint fingerprint) writes them. Cross-key checks (joint order, friction thresholds, time step against
// the stiffest element) stay in validate().
#include "core/config_schema.hpp"
#include "mbd/mechanism_params.hpp"

namespace mbd {

const core::Schema<MechanismParams>& mechanism_schema();

}  // namespace mbd
