#pragma once
// Squeeze flow of a compacted bed out of the nip (flow.effects.squeeze_flow, a candidate of the diagnosis). Rock at
// the compaction limit leaves the nip only by sliding along both liners toward the cell below. A slice of the layer
// (thickness g between two walls with Coulomb friction mu, the walls' normal stress taken equal to the layer's
// pressure) balances g dp/dx = 2 mu p, so the pressure needed a distance x upstream of where the rock is free rises as
// p(x) = p0 exp(2 mu x / g): the friction hill of a layer pressed between rough plates (the slab method of plane-strain
// forging with Coulomb friction). Over a path of changing thickness, p / p0 = exp(2 mu J), J = the integral of dx / g
// from where the rock is free (the discharge, or a cell below with room) to the point. Without it (the shipped
// model) a bed at the limit flows out at p0 however thin.
#include <algorithm>
#include <cmath>

namespace chamber {

// e^40: no bed reaches it (the mantle stops far earlier); it keeps p finite as g -> 0.
constexpr double kMaxSqueezeExponent = 40.0;

// dx / g of a piece of the path, length x (m) at thickness g (m); a closed gap: as far as the cap.
inline double squeeze_path(double x, double g) { return g > 0 ? x / g : kMaxSqueezeExponent; }

// p / p0 at the end of a path with J = sum of squeeze_path over it, wall friction mu.
inline double squeeze_flow_factor(double mu, double J) {
  if (mu <= 0 || J <= 0) return 1.0;
  return std::exp(std::min(2.0 * mu * J, kMaxSqueezeExponent));
}

}  // namespace chamber
