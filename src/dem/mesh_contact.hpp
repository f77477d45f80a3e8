#pragma once
// Particle-mesh contact (a moving rigid liner), a dem::Interaction called by World every step.
//
// Narrow phase: closest point of each candidate triangle to the particle centre (face, edge or
// vertex). A contact on an edge or vertex is kept only when it is the closest point for EVERY
// triangle sharing that feature (the centre lies in the feature's Voronoi region); contacts whose
// points coincide (within 1e-9 r) are merged. So a sphere on a flat tessellated plane gets exactly
// one contact anywhere (inside a face, on a shared edge, at a shared vertex), a sphere on a convex
// edge gets one edge contact, and a sphere in a concave corner gets one contact per face it touches.
// The law is demcore's hertz_mindlin() (paper Eq. 16-19 + CDT rolling friction) with the
// particle-wall material pair, the wall of infinite mass and radius (r* = r_i, M* = m_i).
// Meshes are two-sided: the normal points from the closest surface point to the particle centre.
// Relative velocity at the contact point q: particle surface minus wall v + w x (q - origin); the
// rolling friction uses the spin relative to the wall (w_i - w_wall), so a particle carried round
// by a turning liner feels none.
//
// Tangential history is kept per (particle id, triangle). A new contact on a triangle takes over the
// history of the same particle's previous contact on another triangle that is no longer touched and
// whose normal is within 45 degrees (the contact slid onto a neighbour); the spring is then rotated
// into the new tangent plane by hertz_mindlin().
//
// Broad phase: a uniform grid over the triangles in the body frame (mesh_grid.hpp), rebuilt only
// when a particle larger than its margin (less the skin) appears. A particle with no triangle within r + skin is
// skipped until it has moved skin / 2 in the body frame (the mesh's motion included), which cannot bring it into
// contact: the results are those without the skip, bit for bit. OpenMP over particles with a static schedule;
// per-contact records are concatenated in particle order and reduced serially, so results are
// bit-identical for any thread count.
//
// Domain decomposition: ghosts (set_ghosts) are skipped, so a rank's totals are its owned particles' share; World::assemble
// puts the parts' histories and totals together (assemble_state). The ghost mask is not in the checkpoint: the
// decomposition sets it again after a load.
//
// Checkpoint (save_state/load_state, called by World's): the tangential histories of the last step (per
// particle id and triangle, with their normals for the hand-over), the broad-phase grid's margin and cell (the
// grid is built lazily from the largest radius present at its first use; it is rebuilt the same on load, so the
// restored object also keeps its cost), the pose and twist, and the last step's totals (wrench, total and
// per-region normal force, worst overlap). contacts() is empty after a load until the next step. The caller
// still sets the pose and twist before each step as usual.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "dem/interaction.hpp"
#include "dem/materials.hpp"
#include "dem/mesh.hpp"
#include "dem/mesh_geometry.hpp"
#include "dem/mesh_grid.hpp"
#include "dem/region_map.hpp"

namespace dem {

// One particle-triangle contact of the last step (world frame).
struct MeshContactRecord {
  uint64_t particle_id;
  int particle_index;
  int triangle;
  TriFeature feature;
  int region;                  // region of the triangle, -1 without a region map
  double overlap = 0;              // m
  Eigen::Vector3d point = Eigen::Vector3d::Zero();       // contact point on the mesh, world
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();      // unit, from the mesh towards the particle centre
  Eigen::Vector3d force = Eigen::Vector3d::Zero();       // on the particle (the mesh gets -force), N
  Eigen::Vector3d roll_torque = Eigen::Vector3d::Zero(); // rolling torque on the particle (the mesh gets the opposite), N m
  double normal_force = 0;         // signed normal force along `normal` (Eq. 16), N
  Eigen::Vector3d history = Eigen::Vector3d::Zero();     // tangential spring (m)
};

struct MeshWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // on the mesh, N, world frame
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // on the mesh about `point`, N m, world frame
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

class MeshContact : public Interaction {
 public:
  // wall_material: index of the mesh's material in `materials`; every particle material used must
  // have a pair with it (checked on first use, std::invalid_argument otherwise).
  MeshContact(TriMesh mesh, const MaterialTable& materials, int wall_material);

  TriMesh& mesh() { return mesh_; }  // set_pose()/set_twist() on it every step
  const TriMesh& mesh() const { return mesh_; }
  int wall_material() const { return wall_material_; }  // its index in the MaterialTable
  void set_pose(const Pose& p) { mesh_.set_pose(p); }
  void set_twist(const Twist& t) { mesh_.set_twist(t); }
  // Optional region map (must match the mesh's triangle count).
  void set_regions(RegionMap regions);
  const RegionMap* regions() const { return regions_ ? &*regions_ : nullptr; }

  // OpenMP threads (0: omp_get_max_threads()); results do not depend on it.
  void set_threads(int n) { threads_ = n < 0 ? 0 : n; }
  // Broad-phase cell edge (m); <= 0 (default) lets TriangleGrid choose. Takes effect at the next build.
  void set_grid_cell(double h) { grid_cell_ = h; grid_ = TriangleGrid(); }
  // Skin of the far-particle skip, as a fraction of the largest radius (0: off). A particle found with no
  // triangle within r + skin is skipped until it has moved skin / 2 relative to the mesh (in the body frame), so
  // the contacts and forces are exactly those without the skip. Takes effect at the next build.
  void set_skin_fraction(double f) { skin_fraction_ = f < 0 ? 0 : f; grid_ = TriangleGrid(); }
  // Particle narrow-phase evaluations (grid queries) of the last step; the others were skipped as far.
  long evaluated() const { return evaluated_; }
  void on_reindex(const std::vector<long>& old_to_new) override;
  // Ghosts of a domain decomposition are skipped: no contact, force or history; out of the totals. The histories kept
  // are the owned particles' (a cut World's mesh comes with the whole charge's: the others' are their owners').
  void set_ghosts(const Particles& p, const std::vector<char>& ghost) override;
  // The parts' histories (each of the particles its World owned) together, their totals summed (the worst overlap's
  // index is -1: the parts' indices are not this World's), the pose, twist and grid of the first part. Throws
  // std::invalid_argument when a part is not a MeshContact on the same mesh or a history is in two parts.
  void assemble_state(const std::vector<const Interaction*>& parts) override;
  void on_radius_change(long i) override;  // i is evaluated at the next step

  void add_forces(Particles& p, double t, double dt) override;

  // Results of the last add_forces().
  const std::vector<MeshContactRecord>& contacts() const { return contacts_; }
  // Force and torque on the mesh about `point` (world), equal and opposite to the particles' reactions.
  MeshWrench wrench_about(const Eigen::Vector3d& point) const;
  // Sum over contacts of the normal force magnitude on the mesh (N).
  double total_normal_force() const { return total_normal_; }
  std::pair<double, long> worst_overlap() const override { return {worst_ratio_, worst_index_}; }
  std::string label() const override { return "mesh '" + mesh_.name() + "'"; }
  // Per region: summed normal force (N) and summed force vector on the mesh (N); empty without a map.
  const std::vector<double>& region_normal_force() const { return region_normal_; }
  const std::vector<Eigen::Vector3d>& region_force() const { return region_force_; }
  const TriangleGrid& grid() const { return grid_; }

  // Checkpoint (block "MESH"); load_state needs a MeshContact on a mesh with the same triangle count (and the
  // same region count when the file has per-region totals) and throws std::runtime_error otherwise.
  void save_state(core::BinaryWriter& w) const override;
  void load_state(core::BinaryReader& r) override;

 private:
  struct TriData {  // body-frame geometry for the narrow phase
    Eigen::Vector3d a, b, c, n;
  };
  struct Old {  // previous step's contact, sorted by (particle id, triangle)
    uint64_t id;
    int tri;
    Eigen::Vector3d normal, history;
  };

  TriMesh mesh_;
  MaterialTable materials_;
  int wall_material_;
  int threads_ = 0;
  double grid_cell_ = 0.0;
  std::vector<TriData> tri_;
  std::vector<double> plane_;  // per triangle n.x, n.y, n.z, -n.a (32 bytes: one cache line holds two)
  TriangleGrid grid_;
  std::optional<RegionMap> regions_;

  std::vector<Old> old_;
  std::vector<char> ghost_;  // per particle index: 1 a ghost (skipped); empty: none
  // far-particle skip (per particle index): body-frame centre when last evaluated, and whether no triangle was
  // within r + skin then (0: evaluate)
  double skin_fraction_ = 0.1, skin_ = 0.0;
  std::vector<Eigen::Vector3d> c0_;
  std::vector<uint8_t> far_;
  long evaluated_ = 0;
  std::vector<MeshContactRecord> contacts_;
  std::vector<std::vector<MeshContactRecord>> per_thread_;
  Eigen::Vector3d force_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_origin_ = Eigen::Vector3d::Zero();  // about the world origin
  double total_normal_ = 0.0;
  double worst_ratio_ = 0.0;  // largest overlap / radius of the last step (first such contact in particle order)
  long worst_index_ = -1;
  std::vector<double> region_normal_;
  std::vector<Eigen::Vector3d> region_force_;
};

}  // namespace dem
