#pragma once
// Stand-in mechanism for testing the diagnosis machinery without the MBD library: closed-form periodic
// signals whose dependence on each candidate effect mimics the physics (shape, not magnitude):
//  joint_friction: extra torque c (power + c w) and a phase lag of the cone motion;
//  absorber_nonlinearity: amplitude reduced by the stiffening spring, third harmonic appears;
//  motor_droop: speed drops in proportion to torque ripple (mean held by the drive set point);
//  cardan_misalignment: universal-joint speed ripple w (1 + b^2/2 cos 2phi) (small-angle form of
//  w2/w1 = cos b / (1 - sin^2 b cos^2 phi)) and the matching inertia torque.
// And one uncertain value (a miscalibration term, factor on its nominal 1): frame.mass_scale m: the frame's
// amplitude falls as 1/m, its phase lag grows, the power's mean falls a little (a heavier frame swings less).
#include <cmath>
#include <string>

#include "analysis/param_set.hpp"
#include "analysis/recording.hpp"

namespace diagtest {

// Several effects at once: each term of the set at its value (the others absent).
inline analysis::Recording synthetic_run(const analysis::ParamSet& p, double w, double seconds, double hz = 1000.0) {
  auto at = [&](const char* name) { return p.count(name) ? p.at(name) : 0.0; };
  const double w0 = 400 * 2 * M_PI / 60;
  const double c = at("joint_friction");
  const double k3 = at("absorber_nonlinearity");
  const double d = at("motor_droop");
  const double b = at("cardan_misalignment") * M_PI / 180;
  const double m = p.count("frame.mass_scale") ? p.at("frame.mass_scale") : 1.0;
  const double A = 5e-3 * std::pow(w / w0, 0.2) / m;
  const double k1 = 2e7;
  const double nl = k3 * A * A / k1;
  const double Aeff = A / (1 + nl), A3 = 0.25 * nl * Aeff;
  const double lag = 0.3 + 2e-4 * c + 0.8 * (m - 1.0);
  const double T0 = 1800 * (w / w0) * (1.0 - 0.3 * (m - 1.0)), T2 = 300;
  analysis::Recording r;
  r.source = "synthetic";
  const int n = static_cast<int>(seconds * hz);
  for (int i = 0; i < n; ++i) {
    const double t = i / hz, ph = w * t, q = ph - lag;
    r.t_s.push_back(t);
    r.x_m.push_back(Aeff * std::cos(q) + A3 * std::cos(3 * q));
    r.y_m.push_back(Aeff * std::sin(q) + A3 * std::sin(3 * q));
    r.z_m.push_back(0.2 * Aeff * std::cos(2 * q + 0.4) + 1e-4);
    const double ripple = T2 * std::cos(2 * ph + 0.5);
    const double T = T0 + c + ripple + 5.0 * w * w * b * b * std::sin(2 * ph);
    const double speed = w * (1 + 0.5 * b * b * std::cos(2 * ph)) - d * ripple / 1000.0;
    r.speed_rad_s.push_back(speed);
    r.power_W.push_back(T * speed);
  }
  return r;
}

inline analysis::Recording synthetic_run(const std::string& effect, double value, double w, double seconds,
                                         double hz = 1000.0) {
  analysis::ParamSet p;
  if (effect != "none") p[effect] = value;
  return synthetic_run(p, w, seconds, hz);
}

}  // namespace diagtest
