#pragma once
// What a logger's resolution does to a channel: quantisation noise (Widrow: uniform error of variance
// q^2/12 when the signal plus noise spans many steps), the part of it that does not average out when
// too little noise dithers the quantiser, and channels that are constant within their resolution
// (a logged set point, e.g. the drive speed written at its set value) and so carry no waveform.
#include <vector>

namespace analysis {

// Smallest non-zero step between distinct values of v (0 when v is constant or empty). Steps below
// 1e-12 of the largest magnitude are floating-point noise, not a resolution, and are ignored.
double estimate_resolution(const std::vector<double>& v);

// Variance of the quantisation error of resolution q: q^2 / 12 (uniform on [-q/2, q/2]).
inline double quantisation_variance(double q) { return q * q / 12.0; }

// Part of the quantisation variance that is a deterministic function of the signal (and so lands on the
// drive's harmonics of a periodic signal instead of averaging out), when white noise of variance
// noise_var dithers it: the error's first Fourier term (period q in the signal) is damped by the noise's
// characteristic function, exp(-2 pi^2 sigma^2 / q^2) in amplitude (Widrow & Kollar 2008, ch. 5), so
// q^2/12 exp(-4 pi^2 sigma^2 / q^2) in power. 0 for q = 0.
double undithered_quantisation_variance(double q, double noise_var);

// A channel that is constant within its resolution q: 98 % of its samples (1st to 99th percentile)
// lie within 2 q, i.e. on at most three adjacent logger steps. Such a channel is a set point (or a
// stuck sensor), not a signal to fit.
bool constant_within_resolution(const std::vector<double>& v, double q);

// Median of v (the value of a set-point channel). 0 for an empty v.
double median(std::vector<double> v);

}  // namespace analysis
