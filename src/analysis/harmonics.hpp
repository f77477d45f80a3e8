#pragma once
// Harmonic decomposition of a signal at a known fundamental (the drive frequency):
//   y(t) ~ c0 + sum_{k=1..K} (a_k cos(k w t) + b_k sin(k w t))
// fitted by linear least squares (exact for any sampling; with uniform sampling over whole periods it
// equals the DFT bins). Complex form used for shifts: C_k = a_k - i b_k, y = Re sum C_k e^{i k w t}.
#include <complex>
#include <vector>

namespace analysis {

struct Harmonics {
  double omega = 0;                          // rad/s, fundamental
  std::vector<std::complex<double>> C;       // C[0] = mean (real), C[k] = a_k - i b_k
  // Variance of what the fit left over and the number of samples: the uncertainty of each estimated
  // coefficient pair is ~ 2 remainder_var / samples (set by model_harmonics; 0 = exact).
  double remainder_var = 0, samples = 0;
  int orders() const { return static_cast<int>(C.size()) - 1; }
  double amplitude(int k) const;             // |C_k| (k >= 1), |mean| for k = 0
  double phase(int k) const;                 // arg of cos(k w t + phase): arg(C_k)
  // Value at time t of the periodic signal delayed by tau: y(t - tau).
  double value(double t, double tau = 0.0) const;
  // Mean power of order k over a period: C0^2 for k = 0, |C_k|^2 / 2 for k >= 1.
  double power(int k) const;
};

// Least-squares fit of orders 0..K at fundamental omega. Throws std::invalid_argument when there are
// fewer samples than 2K+1 or omega is not positive.
Harmonics fit_harmonics(const std::vector<double>& t, const std::vector<double>& y, double omega, int K);
// Residual of y after removing the fitted harmonics.
std::vector<double> harmonic_remainder(const std::vector<double>& t, const std::vector<double>& y,
                                       const Harmonics& h);
// Refines a fundamental estimate within omega0*(1 +- rel): maximises the power explained by orders
// 1..K summed over the given signals (golden-section search after a coarse scan).
double refine_fundamental(const std::vector<double>& t, const std::vector<const std::vector<double>*>& ys,
                          double omega0, double rel, int K);

}  // namespace analysis
