#include "core/nelder_mead.hpp"

#include <algorithm>
#include <stdexcept>

namespace core {

MinimumN nelder_mead(const std::function<double(const std::vector<double>&)>& f, const std::vector<double>& x0,
                     const std::vector<double>& step, double f_tol, int max_evaluations) {
  const std::size_t n = x0.size();
  if (n == 0 || step.size() != n) throw std::invalid_argument("nelder_mead: x0 and step must have the same size > 0");
  std::vector<std::vector<double>> x(n + 1, x0);
  std::vector<double> fx(n + 1);
  int evals = 0;
  auto eval = [&](const std::vector<double>& p) { return ++evals, f(p); };
  for (std::size_t i = 0; i < n; ++i) x[i + 1][i] += step[i];
  for (std::size_t i = 0; i <= n; ++i) fx[i] = eval(x[i]);
  auto along = [&](const std::vector<double>& c, const std::vector<double>& w, double t) {
    std::vector<double> p(n);
    for (std::size_t k = 0; k < n; ++k) p[k] = c[k] + t * (w[k] - c[k]);
    return p;
  };
  while (evals < max_evaluations) {
    std::vector<std::size_t> order(n + 1);
    for (std::size_t i = 0; i <= n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return fx[a] < fx[b]; });
    const std::size_t best = order[0], worst = order[n], second = order[n - 1];
    if (fx[worst] - fx[best] < f_tol) break;
    std::vector<double> c(n, 0.0);  // centroid of all but the worst
    for (std::size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (std::size_t k = 0; k < n; ++k) c[k] += x[i][k] / n;
    const auto r = along(c, x[worst], -1.0);
    const double fr = eval(r);
    if (fr < fx[best]) {
      const auto e = along(c, x[worst], -2.0);
      const double fe = eval(e);
      if (fe < fr) x[worst] = e, fx[worst] = fe; else x[worst] = r, fx[worst] = fr;
    } else if (fr < fx[second]) {
      x[worst] = r, fx[worst] = fr;
    } else {
      const auto k = along(c, fr < fx[worst] ? r : x[worst], 0.5);
      const double fk = eval(k);
      if (fk < std::min(fr, fx[worst])) {
        x[worst] = k, fx[worst] = fk;
      } else {
        for (std::size_t i = 0; i <= n; ++i)
          if (i != best) x[i] = along(x[best], x[i], 0.5), fx[i] = eval(x[i]);
      }
    }
  }
  const std::size_t b = std::min_element(fx.begin(), fx.end()) - fx.begin();
  return {x[b], fx[b], evals};
}

}  // namespace core
