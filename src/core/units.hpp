#pragma once
// Unit conversions applied once, at config load (DESIGN.md: SI inside).
#include <cmath>

namespace core::units {
constexpr double kPi = 3.14159265358979323846;
constexpr double N_per_mm = 1e3;        // N/mm -> N/m
constexpr double Ns_per_mm = 1e3;       // N s/mm -> N s/m
constexpr double mm = 1e-3;             // mm -> m
constexpr double mm_per_s = 1e-3;       // mm/s -> m/s
constexpr double deg = kPi / 180.0;     // deg -> rad
constexpr double rpm = 2.0 * kPi / 60.0;  // rpm -> rad/s
constexpr double GPa_per_m = 1e9;       // GPa/m -> Pa/m
constexpr double MPa = 1e6;             // MPa -> Pa
constexpr double GPa = 1e9;
constexpr double kN = 1e3;
// Stiffness of a power law F = k d^h given in N/mm^h, to N/m^h: k * 1000^h (Table 1, Eq. 11).
inline double power_law_stiffness_to_si(double k_N_per_mm_h, double h) {
  return k_N_per_mm_h * std::pow(1e3, h);
}
}  // namespace core::units
