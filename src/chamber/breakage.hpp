#pragma once
// Interparticle breakage of one compression event in a bed (Evertsson and Bearman 1997; chamber_models.md
// section 2): p = [B S(s) + I - S(s)] f, f and p the mass by size class before and after, s the event's
// compression ratio. S is diagonal (the share of each class selected), B lower triangular with columns summing
// to one (mass conserved).
//   selection  S_j(s) = 1 - exp(-(s / s_cj)^m),  s_cj = s_c (x_j / x_ref)^(-q)   (coarser classes break sooner)
//              below the smallest size the piston-die test resolves (x_res): s_cj = s_c(x_res) (x_j / x_res)^(-q_below),
//              q_below = a / n (bed_size_exponent): the lump strength's size effect a of the ISRM point-load test,
//              (D / 50 mm)^0.45, carried through the bed's pressure law p = E s^n
//   progeny    B(x; y) = phi (x/y)^gamma + (1 - phi) (x/y)^beta   (Austin's cumulative form, y = top of class j)
// Classes follow ascending sieves x_0 < ... < x_{K-1}: class 0 is the pan (below x_0), class k holds
// (x_{k-1}, x_k], class K what is above the largest sieve. x_j is the geometric mean of its bounds (pan: x_0 / 2,
// top class: x_{K-1} sqrt 2).
#include <vector>

namespace chamber {

// The lump strength's size effect, ISRM point-load test: Is50 = (D / 50 mm)^0.45 Is, so strength ~ D^-0.45.
constexpr double kPointLoadSizeExponent = 0.45;

// Size exponent of s_c of lumps in a bed: a lump of size x is loaded by the bed's pressure (contact forces ~ p x^2)
// and fails at a force ~ strength x^2, so it breaks at a bed pressure p_c ~ strength ~ x^-a; the bed reaches p at
// s = (p / E)^(1 / n), so s_c ~ x^(-a / n). (Not the strain to failure: a bed's compression is mostly rearrangement.)
inline double bed_size_exponent(double strength_exponent, double pressure_exponent) {
  return strength_exponent / pressure_exponent;
}

struct BreakageParams {
  double s_c = 0.25;      // compression ratio at which a class of size x_ref is 63 % selected
  double m = 2.0;         // selection exponent
  double q = 0.5;         // size exponent of s_c
  double x_ref = 10e-3;   // m
  double x_resolved = 0;  // m: smallest size the selection law was measured at (0: the law holds at every size)
  double q_below = bed_size_exponent(kPointLoadSizeExponent, 2.0);  // size exponent of s_c below x_resolved (at n = 2)
  double phi = 0.4, gamma = 0.8, beta = 3.0;  // progeny
};

// s_cj of a class of representative size x (m): the law above, continuous at x_resolved.
double critical_compression(const BreakageParams& p, double x);

class Breakage {
 public:
  // sieves: ascending, m. Throws std::invalid_argument for bad sieves or parameters.
  Breakage(const std::vector<double>& sieves, const BreakageParams& p);
  std::size_t classes() const { return x_.size(); }
  double size(std::size_t j) const { return x_[j]; }    // representative size of class j (m)
  double lower(std::size_t j) const { return lo_[j]; }  // lower bound (m, 0 for the pan)
  double upper(std::size_t j) const { return up_[j]; }  // upper bound (m; top class: largest sieve x sqrt 2)
  double selection(std::size_t j, double s) const { return selection_between(j, 0.0, s); }  // S_j(s)
  // Share of class j selected by a pressing from compaction s0 on to s1 (loose-referenced), by the rise of the hazard
  // (s / s_cj)^m: 1 - exp(-((s1 / s_cj)^m - (s0 / s_cj)^m)), so that pressings 0 -> s0 -> s1 select as one to s1.
  double selection_between(std::size_t j, double s0, double s1) const;
  double b(std::size_t i, std::size_t j) const { return B_[i * x_.size() + j]; }  // class j -> class i (i <= j)
  // One event of compression ratio s applied in place to the mass vector f (kg per class).
  void apply(double s, double* f) const { apply_between(0.0, s, f); }
  // A pressing that takes rock already compacted to s0 on to s1: p = [B S + I - S] f with S = selection_between.
  void apply_between(double s0, double s1, double* f) const;

 private:
  BreakageParams p_;
  std::vector<double> x_, lo_, up_, sc_, B_;  // sc_: s_cj per class
  mutable std::vector<double> work_;
};

}  // namespace chamber
