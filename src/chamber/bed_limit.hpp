#pragma once
// What a bed does when the liners press it past its compaction limit s_max (the solid's density in the shipped rock:
// no voids left to close). Two laws (flow.material.pressure.at_limit):
//   extrude: the excess rock is pressed out of the nip into the cell below at the limit's pressure E s_max^n
//            (FlowModel::step), however far the liner goes.
//   elastic: the rock is held; the liner's further approach compresses the locked layer elastically, along the
//            bed law's own reloading stiffness at the limit (mbd/bed_law.hpp: the unloading branch from s_max,
//            p = E s_max^n ((e - er) / (rebound s_max))^n, has the tangent n E s_max^n / (rebound s_max) there), with no
//            loss and no extrusion: the rock leaves only by falling when the gap opens (Evertsson).
// The locked layer's strain: a cell holding m kg whose gap holds m_max kg at the limit is squeezed to m_max / m of its
// thickness at the limit, eps = 1 - m_max / m; per unit eps the law's strain e = 1 - cap / m moves by (1 - s_max).

namespace chamber {

// The locked layer's stiffness dp/deps (Pa) for the law p = E s^n with `rebound`; p_limit = E s_max^n. A constant of
// the material (FlowModel derives it once).
inline double locked_bed_stiffness(double n, double rebound, double s_max, double p_limit) {
  const double k_e = n * p_limit / (rebound * s_max);  // the reloading tangent dp/de at the limit
  return k_e * (1.0 - s_max);
}

// Pressure added above the limit's for a locked layer strained eps (Pa); none for eps <= 0.
inline double locked_bed_pressure(double eps, double stiffness) { return eps > 0 ? stiffness * eps : 0.0; }

}  // namespace chamber
