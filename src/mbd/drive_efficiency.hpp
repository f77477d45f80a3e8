#pragma once
// The drive's losses between the motor's terminals and the drive shaft (effects.drive_efficiency): what the plant
// logs is the motor's input power (paper section 4.1.2: "the data indicate the input power of the drive motor").
#include <cmath>

#include "mbd/mechanism_params.hpp"

namespace mbd {

// Motor input power (W) for a drive-shaft power `shaft_W` at `speed_rad_s`: shaft / efficiency while motoring,
// shaft x efficiency while the shaft drives the motor back (regeneration), plus the no-load loss
// P0 (|w| / w_ref)^k. Disabled: shaft_W unchanged.
inline double motor_input_power(const DriveEfficiency& d, double shaft_W, double speed_rad_s) {
  if (!d.enabled) return shaft_W;
  const double conv = shaft_W >= 0 ? shaft_W / d.efficiency : shaft_W * d.efficiency;
  const double no_load =
      d.no_load_W > 0 ? d.no_load_W * std::pow(std::abs(speed_rad_s) / d.reference_speed_rad_s, d.speed_exponent) : 0.0;
  return conv + no_load;
}

}  // namespace mbd
