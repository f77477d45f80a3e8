#pragma once
// Small derivative-free optimisers used with the simulation in the loop.
#include <functional>
#include <vector>

#include "core/nelder_mead.hpp"

namespace analysis {

struct Minimum {
  double x = 0, f = 0;
  int evaluations = 0;
};

// Golden-section search for a minimum of f on [a, b], to an interval width tol (Kiefer 1953).
Minimum golden_section(const std::function<double(double)>& f, double a, double b, double tol,
                       int max_evaluations = 200);
// Coarse scan of n equally spaced points on [a, b] (guards against several local minima), then
// golden-section on the bracket around the best point. Returns the best point seen.
Minimum minimise_scan_golden(const std::function<double(double)>& f, double a, double b, int n, double tol);
// The same for a function of period P: n points on [0, P), the bracket wraps around 0 (a minimum just below 0
// is found at P - x, not clipped to 0). Returns x in [0, P).
Minimum minimise_periodic_scan_golden(const std::function<double(double)>& f, double period, int n, double tol);
// Second derivative of f at x by central differences with step h (f(x) known as fx).
double second_derivative(const std::function<double(double)>& f, double x, double fx, double h);

using core::MinimumN;
using core::nelder_mead;

}  // namespace analysis
