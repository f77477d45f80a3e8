#pragma once
// The jackknife standard error of an estimate from its leave-one-out values x_(i) (the estimate recomputed without
// sample i, i = 1..K): sqrt((K - 1) / K sum (x_(i) - mean x_(.))^2) (Efron & Tibshirani, An Introduction to the
// Bootstrap, eq. 11.5). For the mean of K samples it is their sample std / sqrt(K) exactly. NaN for fewer than two
// values or a NaN among them.
#include <cmath>
#include <vector>

namespace analysis {

inline double jackknife_std(const std::vector<double>& leave_one_out) {
  const double K = static_cast<double>(leave_one_out.size());
  if (leave_one_out.size() < 2) return std::nan("");
  double mean = 0.0, ss = 0.0;
  for (double x : leave_one_out) mean += x / K;
  for (double x : leave_one_out) ss += (x - mean) * (x - mean);
  return std::sqrt((K - 1.0) / K * ss);
}

}  // namespace analysis
