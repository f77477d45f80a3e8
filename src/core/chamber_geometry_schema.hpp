#pragma once
// The keys of a liner-profile mapping (mbd.chamber's mantle/concave lists), checked as a whole after the last.
#include "core/chamber_geometry.hpp"
#include "core/config_schema.hpp"

namespace core {

const Schema<ChamberGeometry>& chamber_geometry_schema();

}  // namespace core
