#pragma once
// Rigid triangle mesh (a liner surface) with a pose and a twist set from outside every step.
// Geometry is stored once in the body frame; world vertices are a cache refreshed by set_pose().
// Topology (welded vertices, edges with their adjacent triangles) is built once, for contact
// de-duplication across shared edges and vertices (mesh_contact.hpp).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace dem {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          // body origin in world, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body -> world
};

struct Twist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // velocity of the body origin, m/s
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // angular velocity, world frame, rad/s
};

using Triangle = std::array<int, 3>;

class TriMesh {
 public:
  struct Edge {
    int v0, v1;            // v0 < v1
    int tri0, tri1;        // adjacent triangles (tri1 = -1 on a boundary edge)
  };

  TriMesh() = default;
  // Vertices in the body frame, triangles counter-clockwise seen from the side the normal points to.
  // Throws std::invalid_argument on out-of-range indices, degenerate (repeated-index) triangles or
  // non-finite coordinates.
  TriMesh(std::vector<Eigen::Vector3d> vertices, std::vector<Triangle> triangles,
          std::string name = "");
  // Builds a mesh from a triangle soup (e.g. STL), merging vertices closer than weld_tol (m;
  // 0 merges bit-identical coordinates only). Triangles of zero area after welding are dropped.
  static TriMesh from_soup(const std::vector<std::array<Eigen::Vector3d, 3>>& soup,
                           double weld_tol = 0.0, std::string name = "");

  const std::string& name() const { return name_; }
  size_t num_vertices() const { return verts_.size(); }
  size_t num_triangles() const { return tris_.size(); }
  const std::vector<Eigen::Vector3d>& vertices() const { return verts_; }   // body frame
  const std::vector<Triangle>& triangles() const { return tris_; }
  const Eigen::Vector3d& vertex(int v) const { return verts_[v]; }
  const Triangle& triangle(int t) const { return tris_[t]; }
  const Eigen::Vector3d& normal(int t) const { return normals_[t]; }        // unit, body frame
  Eigen::Vector3d centroid(int t) const;                                   // body frame
  double triangle_area(int t) const;
  double area() const;
  // Volume enclosed (divergence theorem; exact for a closed, consistently oriented mesh; positive
  // for outward normals). For an open mesh it is the signed volume of the cone to the body origin.
  double signed_volume() const;
  void flip_normals();  // reverses every triangle's winding

  // Topology.
  const std::vector<Edge>& edges() const { return edges_; }
  // Edge ids of triangle t: edge k joins corners k and (k+1)%3.
  const std::array<int, 3>& triangle_edges(int t) const { return tri_edges_[t]; }
  // Triangles sharing vertex v (CSR).
  std::pair<const int*, const int*> vertex_triangles(int v) const {
    return {vt_idx_.data() + vt_off_[v], vt_idx_.data() + vt_off_[v + 1]};
  }
  bool triangles_share_vertex(int a, int b) const;

  // Rigid motion, set from outside every step.
  void set_pose(const Pose& pose);
  void set_twist(const Twist& twist) { twist_ = twist; }
  const Pose& pose() const { return pose_; }
  const Twist& twist() const { return twist_; }
  const Eigen::Matrix3d& rotation() const { return rot_; }  // body -> world
  Eigen::Vector3d to_world(const Eigen::Vector3d& p_body) const { return rot_ * p_body + pose_.position; }
  Eigen::Vector3d to_body(const Eigen::Vector3d& p_world) const {
    return rot_.transpose() * (p_world - pose_.position);
  }
  // World vertices, transformed once per set_pose() (the cache).
  const std::vector<Eigen::Vector3d>& world_vertices() const { return world_verts_; }
  Eigen::Vector3d world_normal(int t) const { return rot_ * normals_[t]; }
  // Velocity of the material point of the body at world position p: v + w x (p - origin).
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& p_world) const {
    return twist_.linear + twist_.angular.cross(p_world - pose_.position);
  }
  // Axis-aligned bounds of the body-frame vertices.
  Eigen::Vector3d bbox_min() const;
  Eigen::Vector3d bbox_max() const;

 private:
  void build_derived();

  std::string name_;
  std::vector<Eigen::Vector3d> verts_;
  std::vector<Triangle> tris_;
  std::vector<Eigen::Vector3d> normals_;
  std::vector<Edge> edges_;
  std::vector<std::array<int, 3>> tri_edges_;
  std::vector<int> vt_off_, vt_idx_;
  Pose pose_;
  Twist twist_;
  Eigen::Matrix3d rot_ = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Vector3d> world_verts_;
};

}  // namespace dem
