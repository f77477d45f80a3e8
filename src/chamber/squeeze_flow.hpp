#pragma once
// Squeeze flow of a compacted bed out of the nip (flow.effects.squeeze_flow, a candidate of the diagnosis). Rock at
// the compaction limit leaves the nip only by sliding along both liners to where it is free. A slice of the layer
// (thickness g between two walls with Coulomb friction mu, the walls' normal stress taken equal to the layer's
// pressure) balances g dp/dx = 2 mu p, so the pressure needed a distance x upstream of where the rock is free rises as
// p(x) = p0 exp(2 mu x / g): the friction hill of a layer pressed between rough plates (the slab method of plane-strain
// forging with Coulomb friction). x, the escape length, is the candidate's unknown. Without it (the shipped model) a
// bed at the limit flows out at p0 however thin the gap.
#include <algorithm>
#include <cmath>

namespace chamber {

// Caps the factor at e^40 (reached at g = 2 mu x / 40: 0.5 mm for x 15 mm): it keeps p finite as g -> 0; a mantle
// that far into the bed has long stopped.
constexpr double kMaxSqueezeExponent = 40.0;

// p(x) / p0 for a layer of thickness g (m), x (m) upstream of where it is free, wall friction mu.
inline double squeeze_flow_factor(double mu, double x, double g) {
  if (mu <= 0 || x <= 0) return 1.0;
  const double a = g > 0 ? 2.0 * mu * x / g : kMaxSqueezeExponent;
  return std::exp(std::min(a, kMaxSqueezeExponent));
}

}  // namespace chamber
