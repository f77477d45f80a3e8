#pragma once
// Retained fines: the mass of metaparticles crushed to fines (metaparticle_crushing.hpp) kept in the chamber as a
// continuum bed that loads the liners, instead of leaving at once. ROS-free.
//
// Cells are fixed in the concave's liner frame: `bands` along z over the concave's height x `sectors` in azimuth.
// Each holds fines (kg per sieve class) and their mean fall speed.
//  - Load: the fines fill the cell's space between the liners, A g (A: the cell's concave area, g: the local gap along
//    the mantle normal). Loose, they take m / rho_bulk; the strain e = 1 - A g rho_bulk / m presses them along the
//    hysteretic bed law (mbd/bed_law.hpp, virgin loading from e = 0): p A on both liners along the mantle normal.
//    Fines cannot compact past max_strain: a cell pressed further extrudes its excess into the cell below (out of the
//    chamber from the bottom band), so the pressure stays at most E max_strain^n.
//    The coarse rock (the DEM's spheres) carries its own load: fines among it fill its voids without a force of
//    their own until they alone fill the gap (a few kg of fines could not carry the whole gap's load).
//  - Flow: nipped fines (p > 0) are held by the liners; free fines fall under gravity (Evertsson's cone-crusher flow:
//    material falls while the gap opens) into the cell below as long as there is room there (its fines would still
//    be loose), and out of the chamber from the bottom band (discharged, screened by their classes).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/binary_io.hpp"
#include "core/chamber_geometry.hpp"
#include "mbd/bed_law.hpp"

namespace coupling {

struct FinesBedParams {
  bool enabled = false;
  int bands = 22, sectors = 24;
  double bulk_fraction = 0.55;  // solid fraction of loose fines
  double modulus_Pa = 400e6;    // p = E e^n, virgin loading of the fines
  double exponent = 1.5;
  double rebound = 0.15;        // recovered fraction of each compression (the rest is crushing work)
  double max_strain = 0.35;     // compaction limit (0.55 -> 0.85 solid): fines pressed past it are extruded
};

using FinesLoads = core::LinerLoads;  // on each liner, about the given centres of mass (world frame)

class FinesBed {
 public:
  // mantle, concave: liner profiles in their liner frames; classes: sieve classes a deposit is split into;
  // solid_density: kg/m^3 of the rock. Throws std::invalid_argument for a bad parameter.
  FinesBed(const FinesBedParams& p, const core::Profile& mantle, const core::Profile& concave, std::size_t classes,
           double solid_density);

  int bands() const { return p_.bands; }
  int sectors() const { return p_.sectors; }
  std::size_t cells() const { return speed_.size(); }
  // Cell of a point given in the concave's liner frame (band-major); -1 below the bottom band (it leaves at once);
  // points above the top band belong to it.
  long cell_of(const Eigen::Vector3d& xc) const;
  double cell_area(std::size_t k) const { return cells_.area[k / p_.sectors]; }  // m^2 of concave
  // Fines of one crushed lump at xc (concave liner frame), kg per class; below the bottom they are discharged.
  void deposit(const Eigen::Vector3d& xc, const std::vector<double>& class_kg);

  // Presses the fines at the liners' pose (liner frame -> world) and lets the free ones fall for h seconds.
  FinesLoads step(const Eigen::Isometry3d& mantle, const Eigen::Isometry3d& concave, const Eigen::Vector3d& com_mantle,
                  const Eigen::Vector3d& com_concave, double h, double gravity);

  std::vector<double> take_discharged();  // kg per class that left the bottom since the last take
  double mass_kg() const;                 // in the cells, plus what left them but is not yet taken
  double cell_mass(std::size_t k) const;
  double cell_pressure(std::size_t k) const { return pressure_[k]; }  // Pa at the last step
  double cell_gap(std::size_t k) const { return gap_[k]; }            // m at the last step

  void save_state(core::BinaryWriter& w) const;
  void load_state(core::BinaryReader& r);

 private:
  FinesBedParams p_;
  core::Profile mantle_;
  std::size_t classes_;
  double rho_bulk_ = 0;
  core::ConcaveCells cells_;  // the cells' concave points and areas
  std::vector<double> mass_;                       // cells x classes, kg
  std::vector<double> speed_, pressure_, gap_;  // per cell: m/s down, Pa, m
  std::vector<mbd::BedCell> memory_;
  std::vector<double> out_;  // discharged per class, not yet taken

  void extrude(std::size_t k, double fraction);  // moves that fraction of cell k's fines one band down (or out)
};

}  // namespace coupling
