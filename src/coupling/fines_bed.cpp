#include "coupling/fines_bed.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace coupling {
namespace {
constexpr double kPi = 3.14159265358979323846;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("dem.fines_bed: " + what);
}
}  // namespace

FinesBed::FinesBed(const FinesBedParams& p, const core::Profile& mantle, const core::Profile& concave,
                   std::size_t classes, double solid_density)
    : p_(p), mantle_(mantle), classes_(classes) {
  require(p.bands >= 1 && p.sectors >= 1, "bands and sectors must be >= 1");
  require(p.bulk_fraction > 0 && p.bulk_fraction < 1, "bulk_fraction must be in (0, 1)");
  require(p.modulus_Pa > 0 && p.exponent >= 1, "modulus must be > 0 and exponent >= 1");
  require(p.rebound > 0 && p.rebound <= 1, "rebound must be in (0, 1]");
  require(p.max_strain > 0 && p.max_strain < 1, "max_strain must be in (0, 1)");
  require(classes >= 1 && solid_density > 0, "needs sieve classes and a rock density");
  rho_bulk_ = p.bulk_fraction * solid_density;
  cells_ = core::concave_cells(concave, std::min(concave.z.front(), concave.z.back()),
                               std::max(concave.z.front(), concave.z.back()), p.bands, p.sectors);
  const std::size_t n = static_cast<std::size_t>(p.bands) * p.sectors;
  mass_.assign(n * classes_, 0.0);
  speed_.assign(n, 0.0);
  pressure_.assign(n, 0.0);
  gap_.assign(n, 0.0);
  memory_.assign(n, mbd::BedCell{});
  out_.assign(classes_, 0.0);
}

long FinesBed::cell_of(const Eigen::Vector3d& xc) const {
  const double u = (xc.z() - cells_.z_lo) / cells_.dz;
  if (u < 0) return -1;
  const int b = std::min(p_.bands - 1, static_cast<int>(u));
  double a = std::atan2(xc.y(), xc.x());
  if (a < 0) a += 2 * kPi;
  const int s = std::min(p_.sectors - 1, static_cast<int>(a / (2 * kPi) * p_.sectors));
  return static_cast<long>(b) * p_.sectors + s;
}

void FinesBed::deposit(const Eigen::Vector3d& xc, const std::vector<double>& class_kg) {
  if (class_kg.size() != classes_) throw std::logic_error("FinesBed::deposit: wrong number of sieve classes");
  const long k = cell_of(xc);
  double* to = k < 0 ? out_.data() : &mass_[static_cast<std::size_t>(k) * classes_];
  for (std::size_t c = 0; c < classes_; ++c) to[c] += class_kg[c];
}

double FinesBed::cell_mass(std::size_t k) const {
  const auto* m = &mass_[k * classes_];
  return std::accumulate(m, m + classes_, 0.0);
}

double FinesBed::mass_kg() const {
  return std::accumulate(mass_.begin(), mass_.end(), std::accumulate(out_.begin(), out_.end(), 0.0));
}

std::vector<double> FinesBed::take_discharged() {
  std::vector<double> o(classes_, 0.0);
  o.swap(out_);
  return o;
}

FinesLoads FinesBed::step(const Eigen::Isometry3d& mantle, const Eigen::Isometry3d& concave,
                          const Eigen::Vector3d& com_m, const Eigen::Vector3d& com_c, double h, double gravity) {
  FinesLoads out;
  const Eigen::Isometry3d to_mantle = mantle.inverse();
  const std::size_t S = static_cast<std::size_t>(p_.sectors);
  for (std::size_t k = 0; k < cells(); ++k) {
    const std::size_t b = k / S, s = k % S;
    // The cell's point on the concave, its gap to the mantle along the mantle's normal there.
    const Eigen::Vector3d X = concave * cells_.point(b, s);
    const Eigen::Vector3d xm = to_mantle * X;
    const double rho = std::hypot(xm.x(), xm.y());
    Eigen::Vector2d nzr;
    const double g = std::max(0.0, -core::signed_distance_inside(mantle_, {xm.z(), rho}, &nzr));
    gap_[k] = g;
    double m = cell_mass(k);
    pressure_[k] = 0;
    // Compaction limit: fines pressed past max_strain flow out of the nip, down into the cell below (or out of the
    // chamber from the bottom band), instead of carrying an ever higher pressure.
    const double m_max = cells_.area[b] * g * rho_bulk_ / (1.0 - p_.max_strain);
    if (m > m_max) {
      extrude(k, m_max > 0 ? 1.0 - m_max / m : 1.0);
      m = m_max;
    }
    if (m <= 0) {
      memory_[k] = mbd::BedCell{};
      continue;
    }
    const double e = std::min(p_.max_strain, std::max(0.0, 1.0 - cells_.area[b] * g * rho_bulk_ / m));
    const double p = mbd::bed_hysteretic(memory_[k], e, p_.modulus_Pa, p_.exponent, p_.rebound).p;
    pressure_[k] = p;
    if (p <= 0) continue;
    const Eigen::Vector3d n_local(nzr.y() * xm.x() / std::max(rho, 1e-12), nzr.y() * xm.y() / std::max(rho, 1e-12),
                                  nzr.x());
    const Eigen::Vector3d n = mantle.linear() * n_local;  // out of the mantle, towards the concave
    const Eigen::Vector3d F = p * cells_.area[b] * n;        // on the concave; -F on the mantle
    out.f_concave += F;
    out.t_concave += (X - com_c).cross(F);
    out.f_mantle -= F;
    out.t_mantle += (X - g * n - com_m).cross(-F);
    out.normal_force += p * cells_.area[b];
  }
  // Free fines fall, bottom band first (so that what leaves a cell makes room above it in the same step).
  for (std::size_t k = 0; k < cells(); ++k) {
    const std::size_t b = k / S;
    const double m = cell_mass(k);
    if (m <= 0 || pressure_[k] > 0) {
      speed_[k] = 0;
      continue;
    }
    speed_[k] += gravity * h;
    double move = m * std::min(1.0, speed_[k] * h / cells_.dz);
    double* from = &mass_[k * classes_];
    double* to = out_.data();
    if (b > 0) {
      const std::size_t below = k - S;
      const double mb = cell_mass(below);
      move = std::min(move, std::max(0.0, rho_bulk_ * (cells_.area[b - 1] * gap_[below]) - mb));
      if (move <= 0) {
        speed_[k] = 0;  // the cell below is full: the fines pile up
        continue;
      }
      speed_[below] = (mb * speed_[below] + move * speed_[k]) / (mb + move);
      to = &mass_[below * classes_];
    }
    const double f = move / m;
    for (std::size_t c = 0; c < classes_; ++c) {
      to[c] += f * from[c];
      from[c] -= f * from[c];
    }
  }
  return out;
}

void FinesBed::extrude(std::size_t k, double fraction) {
  const std::size_t S = static_cast<std::size_t>(p_.sectors);
  double* from = &mass_[k * classes_];
  double* to = k < S ? out_.data() : &mass_[(k - S) * classes_];
  for (std::size_t c = 0; c < classes_; ++c) {
    const double d = fraction * from[c];
    to[c] += d;
    from[c] -= d;
  }
}

void FinesBed::save_state(core::BinaryWriter& w) const {
  w.tag("FINE");
  w.put<int64_t>(p_.bands);
  w.put<int64_t>(p_.sectors);
  w.put_vec(mass_);
  w.put_vec(speed_);
  std::vector<double> mem;
  for (const auto& c : memory_) mem.push_back(c.e0), mem.push_back(c.emax);
  w.put_vec(mem);
  w.put_vec(out_);
}

void FinesBed::load_state(core::BinaryReader& r) {
  r.expect("FINE");
  if (r.get<int64_t>() != p_.bands || r.get<int64_t>() != p_.sectors) r.fail("fines-bed cells differ");
  const std::size_t n = cells();
  std::vector<double> mem;
  r.get_vec(mass_);
  r.get_vec(speed_);
  r.get_vec(mem);
  r.get_vec(out_);
  if (mass_.size() != n * classes_ || speed_.size() != n || mem.size() != 2 * n ||
      out_.size() != classes_)
    r.fail("fines bed is corrupt");
  for (std::size_t k = 0; k < n; ++k) memory_[k] = {mem[2 * k], mem[2 * k + 1]};
}

}  // namespace coupling
