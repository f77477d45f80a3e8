#pragma once
// Forces between the mantle (floating cone B2) and the concave (fixed cone B1), computed by our code
// between the two surfaces of revolution (no ODE contact joints):
//  - cone contact (Eq. 11 normal force, Eq. 13-15 friction) at the closest approach of the surfaces;
//  - the equivalent material bed (distributed compression of the bed along the local normals).
// Sampling: the mantle surface is sampled on a grid fixed in the floating cone (azimuth x generator);
// each sample point is mapped into the concave's liner frame, where its signed distance to the concave
// meridian polyline is the local gap g (closest approach in the meridian plane) and the polyline normal
// is the force direction. The contact uses the mantle profile vertices (where two cones first touch)
// and refines the closest azimuth by a parabola through the three best samples.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "mbd/bed_law.hpp"
#include "mbd/mechanism_params.hpp"

namespace mbd {

struct RigidKinematics {
  Eigen::Vector3d x;  // COM
  Eigen::Matrix3d R;  // body to world
  Eigen::Vector3d v, w;
  Eigen::Vector3d liner_origin;  // liner frame origin in body coordinates
  Eigen::Matrix3d inv_inertia_world;
  double inv_mass = 0;
};

// Wrench on a body about its COM (world), split in a conservative and a dissipative part so the
// energy audit can book them.
struct Wrench {
  Eigen::Vector3d f_cons = Eigen::Vector3d::Zero(), t_cons = Eigen::Vector3d::Zero();
  Eigen::Vector3d f_diss = Eigen::Vector3d::Zero(), t_diss = Eigen::Vector3d::Zero();
  void add(const Eigen::Vector3d& arm, const Eigen::Vector3d& fc, const Eigen::Vector3d& fd) {
    f_cons += fc;
    t_cons += arm.cross(fc);
    f_diss += fd;
    t_diss += arm.cross(fd);
  }
};

struct ChamberForceResult {
  Wrench on_mantle, on_concave;  // contact + bed together
  Wrench contact_on_mantle, contact_on_concave;
  Wrench bed_on_mantle, bed_on_concave;
  double min_gap = 0;             // m
  double contact_normal_force = 0;  // N
  double bed_normal_force = 0;      // N (sum)
  double contact_potential = 0;     // J
  double bed_potential = 0;         // J: elastic energy of the bed (hysteretic: recoverable part)
};

using BedState = std::vector<BedCell>;  // hysteretic bed memory, one cell per mantle patch

class ChamberForces {
 public:
  explicit ChamberForces(const MechanismParams& p);
  // mantle = floating cone B2, concave = fixed cone B1. bed: include the material bed. The hysteretic
  // bed reads its memory from `state` (initial_bed_state() at rest) and, when `next` is given, writes the
  // memory after this configuration to it; the viscous bed ignores both.
  ChamberForceResult compute(const RigidKinematics& mantle, const RigidKinematics& concave, bool bed,
                             double dt, const BedState* state = nullptr, BedState* next = nullptr) const;
  BedState initial_bed_state() const { return BedState(bed_samples_.size()); }
  // State the contact search carries from one compute() to the next: per mantle profile vertex, the
  // azimuth sample where the last hill-climb ended (its next start). Saved and restored by checkpoints.
  const std::vector<int>& contact_search_state() const { return contact_k_; }
  // Throws std::invalid_argument unless there is one entry in [0, sampling.azimuth) per profile vertex.
  void set_contact_search_state(const std::vector<int>& k);
  // Local gap (m) of one mantle point given in the mantle liner frame; normal (world) out of the axis.
  double gap(const RigidKinematics& mantle, const RigidKinematics& concave, const Eigen::Vector3d& local,
             Eigen::Vector3d* world_point, Eigen::Vector3d* normal) const;

 private:
  struct Sample {
    Eigen::Vector3d local;  // mantle liner frame
    double area = 0;        // m^2 (bed)
    double g_ref = 0;       // engage_ratio x rest gap (bed)
  };
  struct Hit {
    Eigen::Vector3d P, n;
    double e, e_dot;
    const Sample* s;
    std::size_t k;  // sample index
  };
  core::ProfileDistance concave_;  // the gap of a point to the concave (hot loop)
  std::vector<double> cos_, sin_;
  double contact_rest_gap_ = 0, contact_reach_ = 0;
  MechanismParams p_;
  mutable std::vector<Hit> hits_;  // scratch (no allocation in the step after the first)
  mutable std::vector<int> contact_k_;  // per profile vertex: azimuth sample of the last closest approach
  std::vector<Sample> bed_samples_;
  std::vector<double> contact_z_, contact_r_;  // mantle profile vertices
};

}  // namespace mbd
