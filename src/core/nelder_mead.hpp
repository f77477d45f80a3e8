#pragma once
// Nelder-Mead simplex minimiser, derivative free (for noisy simulation-in-the-loop costs and small fits).
#include <functional>
#include <vector>

namespace core {

struct MinimumN {
  std::vector<double> x;
  double f = 0;
  int evaluations = 0;
};
// Nelder-Mead simplex (Nelder and Mead 1965; reflection 1, expansion 2, contraction 0.5, shrink 0.5) from x0
// with initial steps `step` per coordinate, until the simplex's f values span less than f_tol or max_evaluations.
MinimumN nelder_mead(const std::function<double(const std::vector<double>&)>& f, const std::vector<double>& x0,
                     const std::vector<double>& step, double f_tol, int max_evaluations = 200);

}  // namespace core
