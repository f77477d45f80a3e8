#pragma once
// Closed convex solids that rocks are packed into: the Brazilian/compression disk (cylinder) and
// irregular "crushed rock" polyhedra generated from a seed. Each shape answers the questions a
// packer needs (distance to the boundary, projection inside) and gives a triangle mesh to store.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace rocks {

using Vec3 = Eigen::Vector3d;

struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside (outward normals)
  double volume() const;                   // divergence theorem; > 0 for outward orientation
  double area() const;
  Vec3 min_corner() const;
  Vec3 max_corner() const;
};

class Shape {
 public:
  virtual ~Shape() = default;
  // Distance from an interior point to the boundary (<= 0 outside: minus the distance to the
  // nearest face plane; exact inside for a convex solid).
  virtual double clearance(const Vec3& p) const = 0;
  // Moves p so that clearance(p) >= r (approximately, for polytopes: one projection per face).
  virtual Vec3 push_inside(const Vec3& p, double r) const = 0;
  virtual double volume() const = 0;
  virtual Vec3 min_corner() const = 0;
  virtual Vec3 max_corner() const = 0;
  virtual TriMesh mesh() const = 0;
  virtual std::string name() const = 0;
};

// Circular cylinder centred at the origin, axis along y (so a Brazilian test loads it along z).
class CylinderShape : public Shape {
 public:
  CylinderShape(double diameter, double length, int segments = 64);
  double clearance(const Vec3& p) const override;
  Vec3 push_inside(const Vec3& p, double r) const override;
  double volume() const override;
  Vec3 min_corner() const override;
  Vec3 max_corner() const override;
  TriMesh mesh() const override;
  std::string name() const override { return name_; }
  double diameter() const { return 2.0 * radius_; }
  double length() const { return length_; }

 private:
  double radius_, length_;
  int segments_;
  std::string name_;
};

// Convex polyhedron: intersection of half-spaces n_k . p <= d_k (|n_k| = 1, d_k > 0).
class PolyhedronShape : public Shape {
 public:
  PolyhedronShape(std::vector<Vec3> normals, std::vector<double> offsets, std::string name);
  double clearance(const Vec3& p) const override;
  Vec3 push_inside(const Vec3& p, double r) const override;
  double volume() const override { return volume_; }
  Vec3 min_corner() const override { return mesh_.min_corner(); }
  Vec3 max_corner() const override { return mesh_.max_corner(); }
  TriMesh mesh() const override { return mesh_; }
  std::string name() const override { return name_; }
  const std::vector<Vec3>& normals() const { return normals_; }
  const std::vector<double>& offsets() const { return offsets_; }

 private:
  std::vector<Vec3> normals_;
  std::vector<double> offsets_;
  std::string name_;
  TriMesh mesh_;
  double volume_;
};

// An irregular rock of nominal size `size` (its extent along y, the intermediate axis that a
// square-mesh sieve measures), made from seed: an ellipsoid with axes a >= b >= c (aspect ratios
// b/a in [0.65, 0.9], c/b in [0.6, 0.9]) chipped by `facets` random planes at depths of 0-25 %
// of the ellipsoid's support distance, then scaled so the y extent is `size`. Same seed, same rock.
std::unique_ptr<PolyhedronShape> make_irregular_rock(unsigned long long seed, double size, int facets = 22,
                                                     const std::string& name = "rock");

// Writes an ASCII STL (units: metres unless scale != 1, e.g. 1e3 for millimetres).
void write_stl(const TriMesh& mesh, const std::string& file, const std::string& solid_name, double scale = 1.0);

}  // namespace rocks
