#pragma once
// The compaction coordinate of the bed's pressure law (chamber_models.md section 3). The hysteretic law of
// mbd/bed_law.hpp is written in u: p = E u^n on virgin loading.
//   power:            u = s,                    p = E s^n (finite at the solid's density)
//   solid_divergence: u = s / (1 - s / s_solid), p = E s_solid^n (s / (s_solid - s))^n, which diverges as the bed
//                     nears the solid's density s_solid = 1 - loose fraction (no bed is denser); the piston-die
//                     pourings fit it better than the power law with the same two parameters (src/chamber/README.md).
// u is monotone in s, so a pressing's loading and unloading in s are the same in u; breakage and volumes stay in s.
#include <limits>

namespace chamber {

struct CompactionScale {
  double limit = std::numeric_limits<double>::infinity();  // s_solid; infinite: the power law
  // (the power law's u = s without its divisions: the same value, s / (1 - s / inf) = s exactly)
  double u(double s) const { return diverges() ? s / (1.0 - s / limit) : s; }
  double s(double u) const { return diverges() ? u / (1.0 + u / limit) : u; }
  bool diverges() const { return limit < std::numeric_limits<double>::infinity(); }
};

}  // namespace chamber
