#include "mbd/contact_law.hpp"

#include <cmath>

namespace mbd {

double normal_force_eq11(const ContactParams& c, double d, double d_dot) {
  if (d <= 0.0) return 0.0;
  const double sgn = (d_dot > 0.0) - (d_dot < 0.0);
  const double f = c.k * std::pow(d, c.h1) + c.c * sgn * std::pow(std::abs(d_dot), c.h2) * std::pow(d, c.h3);
  return f > 0.0 ? f : 0.0;
}

double havsin(double x, double x0, double h0, double x1, double h1) {
  if (x < x0) return h0;
  if (x > x1) return h1;
  constexpr double pi = 3.14159265358979323846;
  return 0.5 * (h0 + h1) + 0.5 * (h1 - h0) * std::sin((x - x0) / (x1 - x0) * pi - 0.5 * pi);
}

double friction_coefficient_eq14(double v, double mu_s, double mu_d, double v_s, double v_d) {
  if (v <= -v_d) return mu_d;
  if (v <= -v_s) return havsin(v, -v_d, mu_d, -v_s, mu_s);
  if (v < v_s) return havsin(v, -v_s, mu_s, v_s, -mu_s);
  if (v < v_d) return havsin(v, v_s, -mu_s, v_d, -mu_d);  // the paper prints (v_s, -mu_d) as end point
  return -mu_d;
}

}  // namespace mbd
