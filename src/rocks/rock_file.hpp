#pragma once
// The rock packing file (*.rock): a packed and bonded breakage particle that a crusher run loads
// instead of repacking. Plain text, SI units, '#' starts a comment line:
//
//   inertia_crusher_rock 1
//   name <word>
//   seed <integer>
//   target_density <number>
//   container_volume_m3 <number>
//   bond_gap_ratio <number>
//   distribution <rest of line>
//   particles <N>
//   <x_m> <y_m> <z_m> <radius_m>          (N lines; shape frame: centred on the rock)
//   bonds <M>
//   <i> <j>                               (M lines; 0-based particle indices, i < j)
//   end
//
// Numbers are written with 17 significant digits, so save -> load is exact.
#include <string>

#include "rocks/packing.hpp"

namespace rocks {

void save_rock(const RockPacking& rock, const std::string& file);
RockPacking load_rock(const std::string& file);  // throws std::runtime_error naming file and line

}  // namespace rocks
