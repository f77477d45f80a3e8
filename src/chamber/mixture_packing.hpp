#pragma once
// The loose solid fraction of a size mixture: de Larrard's compressible packing model (CPM; F. de Larrard, Concrete
// Mixture Proportioning, E & FN Spon 1999, sect. 1.2-1.3). Every class alone packs to the virtual fraction beta (one
// rock, one shape); in a mixture of volume fractions y, with class i dominant, the coarser classes' wall effect and the
// finer classes' loosening give the virtual packing
//   gamma_i = beta / (1 - sum_{d_j > d_i} (1 - beta)(1 - b_ij) y_j - sum_{d_j < d_i} (1 - a_ij) y_j),
//   a_ij = sqrt(1 - (1 - d_j / d_i)^1.02),  b_ij = 1 - (1 - d_i / d_j)^1.50   (de Larrard's fits to binary packings),
// and a placement of compaction index K (4.1 for a loose pour) packs to the Phi that solves
//   K = sum_i (y_i / beta) / (1 / Phi - 1 / gamma_i).
// One size packs to beta K / (1 + K); fine grains fill the coarse grains' voids, so a graded bed packs denser than
// either of its ends.

#include <cstddef>
#include <vector>

namespace chamber {

class MixturePacking {
 public:
  static constexpr double kLoosePour = 4.1;  // K of a simple pour (de Larrard 1999)
  static constexpr std::size_t kMaxClasses = 64;

  // sizes_m: each class's representative size (m, > 0, any order); beta in (0, 1); compaction_index K > 0.
  // Throws std::invalid_argument naming a bad value.
  MixturePacking(const std::vector<double>& sizes_m, double beta, double compaction_index);

  // The solid fraction of the mixture kg (mass per class, any scale, total > 0; one solid density, so mass fractions
  // are volume fractions), to 1e-13. guess: a fraction near it (a cell's last) to start from; 0: none.
  double fraction(const double* kg, double guess = 0) const;
  double beta() const { return beta_; }
  double compaction_index() const { return K_; }
  std::size_t classes() const { return n_; }

  // The beta for which the mixture kg packs to `fraction` at compaction index K (bisection: Phi grows with beta).
  static double beta_for(const std::vector<double>& sizes_m, double compaction_index, const std::vector<double>& kg,
                         double fraction);

 private:
  std::size_t n_;
  double beta_, K_;
  std::vector<double> m_;  // n x n, row i: the interaction of class j with class i dominant (0 on the diagonal)
};

// Mass per class of a bed whose sizes are spread evenly between lo_m and hi_m (m), on the classes bounded by lower and
// upper (m): each class gets its share of the interval. For the piston die's pourings (rocks of 28-40 mm).
std::vector<double> even_size_mixture(const std::vector<double>& lower_m, const std::vector<double>& upper_m, double lo_m,
                                      double hi_m);

}  // namespace chamber
