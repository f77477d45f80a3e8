// Standalone ODE rigs checking the joint and force building blocks against closed forms:
//  - universal joint speed ratio w2/w1 = cos b / (1 - sin^2 b cos^2 theta);
//  - rotating unbalance on springs: steady amplitude and phase.
#include <gtest/gtest.h>
#include <ode/ode.h>

#include <cmath>

namespace {

struct OdeInit {
  OdeInit() { dInitODE2(0); }
};
const OdeInit g_init;

dBodyID make_body(dWorldID w, double mass, double I, double x, double y, double z) {
  dBodyID b = dBodyCreate(w);
  dMass m;
  dMassSetParameters(&m, mass, 0, 0, 0, I, I, I, 0, 0, 0);
  dBodySetMass(b, &m);
  dBodySetPosition(b, x, y, z);
  return b;
}

// Input shaft along z driven at w1; output shaft along (sin b, 0, cos b); cross at the origin.
// theta = input rotation measured from the plane of the two shafts (input yoke axis starts along x,
// in that plane). Returns the largest deviation of w2/w1 from the closed form over two revolutions.
double ujoint_max_error(double b_deg, double* max_ratio, double* min_ratio) {
  const double b = b_deg * M_PI / 180.0;
  dWorldID w = dWorldCreate();
  dWorldSetGravity(w, 0, 0, 0);
  dWorldSetERP(w, 0.2);
  dWorldSetCFM(w, 1e-10);
  dBodyID in = make_body(w, 2.0, 0.02, 0, 0, -0.3);
  const double ox = std::sin(b), oz = std::cos(b);
  dBodyID out = make_body(w, 2.0, 0.02, 0.3 * ox, 0, 0.3 * oz);
  dJointID h1 = dJointCreateHinge(w, nullptr);
  dJointAttach(h1, in, nullptr);
  dJointSetHingeAnchor(h1, 0, 0, -0.3);
  dJointSetHingeAxis(h1, 0, 0, 1);
  dJointSetHingeParam(h1, dParamFMax, 1e6);
  const double w1 = 10.0;
  dJointSetHingeParam(h1, dParamVel, w1);
  dJointID h2 = dJointCreateHinge(w, nullptr);
  dJointAttach(h2, out, nullptr);
  dJointSetHingeAnchor(h2, 0.3 * ox, 0, 0.3 * oz);
  dJointSetHingeAxis(h2, ox, 0, oz);
  dJointID u = dJointCreateUniversal(w, nullptr);
  dJointAttach(u, in, out);
  dJointSetUniversalAnchor(u, 0, 0, 0);
  dJointSetUniversalAxis1(u, 1, 0, 0);  // input yoke, in the plane of the shafts
  dJointSetUniversalAxis2(u, 0, 1, 0);  // output yoke, perpendicular to it and to the output shaft
  // Start the output at its kinematic speed so no transient is needed.
  dBodySetAngularVel(in, 0, 0, w1);
  const double r0 = 1.0 / std::cos(b);
  dBodySetAngularVel(out, w1 * r0 * ox, 0, w1 * r0 * oz);
  const double dt = 1e-4;
  double err = 0, mx = 0, mn = 1e9;
  for (int i = 0; i < static_cast<int>(2 * 2 * M_PI / w1 / dt); ++i) {
    dWorldStep(w, dt);
    const double theta = dJointGetHingeAngle(h1);
    const double r = dJointGetHingeAngleRate(h2) / dJointGetHingeAngleRate(h1);
    const double s = std::sin(b), c = std::cos(theta);
    const double expect = std::cos(b) / (1.0 - s * s * c * c);
    err = std::max(err, std::abs(r - expect));
    mx = std::max(mx, r);
    mn = std::min(mn, r);
  }
  dWorldDestroy(w);
  *max_ratio = mx;
  *min_ratio = mn;
  return err;
}

TEST(Rigs, UniversalJointSpeedRatio) {
  for (double bdeg : {10.0, 20.0, 30.0}) {
    double mx = 0, mn = 0;
    const double err = ujoint_max_error(bdeg, &mx, &mn);
    const double b = bdeg * M_PI / 180;
    // The ripple is (1/cos b - cos b): 0.03 at 10 deg, 0.29 at 30 deg; the error must be far smaller.
    EXPECT_LT(err, 2e-3) << "bend " << bdeg << " deg";
    EXPECT_NEAR(mx, 1.0 / std::cos(b), 2e-3);
    EXPECT_NEAR(mn, std::cos(b), 2e-3);
  }
}

// Base (mass M) on springs k and dampers c in x and y, kept in the xy plane without rotation;
// a rotor of mass m with its COM at eccentricity e turns on a z hinge at constant w.
// (M + m) x'' + c x' + k x = m e w^2 cos(w t): X = m e w^2 / sqrt((k - (M+m) w^2)^2 + (c w)^2),
// lagging the unbalance direction by atan2(c w, k - (M+m) w^2).
void unbalance(double w_drive, double* amp, double* lag) {
  const double M = 100, m = 10, e = 0.1, k = 1e5, c = 1000;
  dWorldID w = dWorldCreate();
  dWorldSetGravity(w, 0, 0, 0);
  dWorldSetERP(w, 0.2);
  dWorldSetCFM(w, 1e-10);
  dBodyID base = make_body(w, M, 5.0, 0, 0, 0);
  dBodyID rotor = make_body(w, m, 0.05, e, 0, 0);
  dJointID plane = dJointCreatePlane2D(w, nullptr);
  dJointAttach(plane, base, nullptr);
  dJointID lock = dJointCreateAMotor(w, nullptr);  // no base rotation about z
  dJointAttach(lock, base, nullptr);
  dJointSetAMotorNumAxes(lock, 1);
  dJointSetAMotorAxis(lock, 0, 0, 0, 0, 1);
  dJointSetAMotorParam(lock, dParamFMax, 1e9);
  dJointSetAMotorParam(lock, dParamVel, 0);
  dJointID h = dJointCreateHinge(w, nullptr);
  dJointAttach(h, rotor, base);
  dJointSetHingeAnchor(h, 0, 0, 0);
  dJointSetHingeAxis(h, 0, 0, 1);
  dJointSetHingeParam(h, dParamFMax, 1e6);
  dJointSetHingeParam(h, dParamVel, w_drive);
  const double dt = 1e-4;
  double sc = 0, ss = 0;
  const double T = 2 * M_PI / w_drive;
  const int settle = static_cast<int>(3.0 / dt);
  const int n = static_cast<int>(std::round(10 * T / dt));
  for (int i = 0; i < settle + n; ++i) {
    const dReal* p = dBodyGetPosition(base);
    const dReal* v = dBodyGetLinearVel(base);
    dBodyAddForce(base, -k * p[0] - c * v[0], -k * p[1] - c * v[1], 0);
    dWorldStep(w, dt);
    if (i >= settle) {
      // Unbalance direction from the rotor COM relative to the base (the angle of the force).
      const dReal* pr = dBodyGetPosition(rotor);
      const dReal* pb = dBodyGetPosition(base);
      const double phi = std::atan2(pr[1] - pb[1], pr[0] - pb[0]);
      // Base displacement along the unbalance direction (in phase) and 90 deg behind it.
      sc += pb[0] * std::cos(phi) + pb[1] * std::sin(phi);
      ss += pb[0] * std::sin(phi) - pb[1] * std::cos(phi);
    }
  }
  dWorldDestroy(w);
  sc /= n;
  ss /= n;
  *amp = std::hypot(sc, ss);
  *lag = std::atan2(ss, sc);
}

TEST(Rigs, RotatingUnbalanceAmplitudeAndPhase) {
  const double M = 100, m = 10, e = 0.1, k = 1e5, c = 1000;
  for (double wd : {20.0, 45.0}) {  // below and above the 30 rad/s resonance
    double amp = 0, lag = 0;
    unbalance(wd, &amp, &lag);
    const double re = k - (M + m) * wd * wd, im = c * wd;
    const double X = m * e * wd * wd / std::hypot(re, im);
    const double phase = std::atan2(im, re);
    EXPECT_NEAR(amp, X, 0.01 * X) << "w " << wd;
    EXPECT_NEAR(lag, phase, 1.0 * M_PI / 180) << "w " << wd;
  }
}

}  // namespace
