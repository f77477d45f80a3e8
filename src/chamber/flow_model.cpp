#include "chamber/flow_model.hpp"

#include "chamber/bed_limit.hpp"
#include "chamber/squeeze_flow.hpp"

#include "chamber/liner_wear.hpp"
#include "core/config_schema.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace chamber {
namespace {
constexpr double kCountedCompression = 0.02;  // events below 2 % compression break (S(s) is small) but are not counted

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("flow: " + what);
}

// Share of a class (bounds lo, up) that passes a gap g: lumps fit through a gap wider than themselves (all from g >= up,
// none up to g <= lo, linearly between). Without branches, so that the loop over the classes vectorises.
double passes(double lo, double up, double g) { return std::clamp((g - lo) / (up - lo), 0.0, 1.0); }
// Points (x, y, z) moved by T, and their distance to the new z axis: a loop that vectorises (distinct arrays;
// -fno-math-errno for this file, CMakeLists.txt).
void to_frame(const Eigen::Isometry3d& T, std::size_t n, const double* __restrict x, const double* __restrict y,
              const double* __restrict z, double* __restrict mx, double* __restrict my, double* __restrict mz,
              double* __restrict rho) {
  const Eigen::Matrix3d& R = T.linear();
  const double r00 = R(0, 0), r01 = R(0, 1), r02 = R(0, 2), r10 = R(1, 0), r11 = R(1, 1), r12 = R(1, 2);
  const double r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2);
  const double tx = T.translation().x(), ty = T.translation().y(), tz = T.translation().z();
  for (std::size_t k = 0; k < n; ++k) {
    mx[k] = r00 * x[k] + r01 * y[k] + r02 * z[k] + tx;
    my[k] = r10 * x[k] + r11 * y[k] + r12 * z[k] + ty;
    mz[k] = r20 * x[k] + r21 * y[k] + r22 * z[k] + tz;
    rho[k] = std::sqrt(mx[k] * mx[k] + my[k] * my[k]);
  }
}
}  // namespace

std::vector<double> default_feed_passing(const std::vector<double>& sieves) {
  std::vector<double> p;
  for (double x : sieves) p.push_back(x >= 50e-3 ? 1.0 : std::pow(x / 50e-3, 2.5));
  return p;
}

FlowParams::FlowParams() : feed_passing(default_feed_passing(sieves_m)) {}

FlowModel::FlowModel(const FlowParams& p, const core::Profile& mantle, const core::Profile& concave)
    : p_(p), mantle_(mantle), breakage_(p.sieves_m, p.material.breakage), draws_(static_cast<std::uint64_t>(p.seed)) {
  const auto& m = p.material;
  require(p.bands >= 2 && p.sectors >= 1, "bands must be >= 2 and sectors >= 1");
  require(m.solid_density > 0 && m.loose_fraction > 0 && m.loose_fraction < 1,
          "needs a solid density > 0 and a loose fraction in (0, 1)");
  require(m.modulus_Pa > 0 && m.exponent >= 1, "pressure law needs modulus > 0 and exponent >= 1");
  require(m.rebound > 0 && m.rebound <= 1, "rebound must be in (0, 1]");
  require(m.max_compression > 0 && m.max_compression <= solid_compaction_limit(m.loose_fraction) + 1e-12,
          "max_compression must be in (0, 1 - loose_solid_fraction]: beyond it the rock would be denser than solid");
  require(!m.solid_divergence || m.max_compression < solid_compaction_limit(m.loose_fraction),
          "pressure.law solid_divergence needs max_compression below the solid limit 1 - loose_solid_fraction = " +
              core::format_number(solid_compaction_limit(m.loose_fraction)) + ", where its pressure is infinite");
  require(!m.solid_divergence || !p.compaction_memory,
          "pressure.law solid_divergence is not implemented with compaction_memory: true (use false)");
  require(!m.elastic_limit || !m.solid_divergence,
          "pressure.at_limit elastic is implemented for pressure.law power only");
  require(m.refill_length_m >= 0 && std::isfinite(m.refill_length_m), "refill.length_mm must be >= 0");
  require(m.refill_length_m == 0 || !p.compaction_memory,
          "refill.length_mm is a law of the hysteretic bed: use it with compaction_memory: false");
  require(m.packing_index >= 0 && std::isfinite(m.packing_index), "packing.compaction_index must be >= 0");
  require(m.packing_index == 0 || (!m.solid_divergence && !p.compaction_memory),
          "packing.compaction_index (the mixture's packing) is implemented for pressure.law power with "
          "compaction_memory: false");
  require(m.packing_index == 0 || (m.packing_ref_min_m > 0 && m.packing_ref_max_m > m.packing_ref_min_m),
          "packing.reference_min_mm and reference_max_mm need 0 < min < max");
  require(m.lump_std >= 0 && m.lump_std <= kMaxLumpStd, "scatter.lump_std must be in [0, " +
                                                           core::format_number(kMaxLumpStd) + "]");
  require(p.feed_passing.size() == p.sieves_m.size(), "feed_passing needs one value per sieve");
  for (std::size_t i = 0; i < p.feed_passing.size(); ++i)
    require(p.feed_passing[i] >= 0 && p.feed_passing[i] <= 1 && (i == 0 || p.feed_passing[i] >= p.feed_passing[i - 1]),
            "feed_passing must be ascending fractions in [0, 1]");
  rho0_ = m.loose_fraction * m.solid_density;
  if (m.elastic_limit)
    locked_stiffness_ = locked_bed_stiffness(m.exponent, m.rebound, m.max_compression,
                                             m.modulus_Pa * std::pow(m.max_compression, m.exponent));
  auto lo = [](const core::Profile& q) { return std::min(q.z.front(), q.z.back()); };
  auto hi = [](const core::Profile& q) { return std::max(q.z.front(), q.z.back()); };
  const double z_lo = std::max(lo(mantle), lo(concave)), z_hi = std::min(hi(mantle), hi(concave));
  require(z_hi > z_lo, "the mantle and the concave share no height");
  const auto& fl = p.effects.feed_limited;
  require(!fl.enabled || (fl.max_feed_kg_s > 0 && std::isfinite(fl.max_feed_kg_s)),
          "effects.feed_limited.max_feed_tph must be > 0");
  const auto& wl = p.effects.worn_liners;
  require(!wl.enabled || (wl.setting_increase_m >= 0 && wl.setting_increase_m <= 0.1 && wl.worn_height_fraction > 0 &&
                          wl.worn_height_fraction <= 1),
          "effects.worn_liners needs setting_increase_mm in [0, 100] and worn_height_fraction in (0, 1]");
  cells_ = core::concave_cells(wl.enabled ? worn_concave(concave, z_lo, z_hi, wl) : concave, z_lo, z_hi, p.bands,
                               p.sectors);
  const auto& lf = p.effects.liner_friction;
  require(!lf.enabled || (lf.wall_friction >= 0 && lf.wall_friction <= 2 && lf.regularisation_m_s > 0 &&
                          lf.regularisation_m_s <= 1),
          "effects.liner_friction needs wall_friction in [0, 2] and regularisation_mm_s in (0, 1000]");
  const auto& sf = p.effects.squeeze_flow;
  require(!sf.enabled || (sf.wall_friction >= 0 && sf.wall_friction <= 2 && sf.escape_length_m >= 0 &&
                          sf.escape_length_m <= SqueezeFlow::kMaxEscapeLength_m),
          "effects.squeeze_flow needs wall_friction in [0, 2] and escape_length_mm in [0, " +
              core::format_number(SqueezeFlow::kMaxEscapeLength_mm) + "]");
  const std::size_t K = p.sieves_m.size();
  for (std::size_t j = 0; j <= K; ++j)
    feed_share_.push_back((j == K ? 1.0 : p.feed_passing[j]) - (j == 0 ? 0.0 : p.feed_passing[j - 1]));
  const std::size_t n = static_cast<std::size_t>(p.bands) * p.sectors;
  mass_.assign(n * classes(), 0.0);
  for (std::size_t j = 0; j < classes(); ++j) lump_kg_.push_back(lump_mass(breakage_.size(j), m.solid_density));
  scatter_.assign(n, 1.0);
  speed_.assign(n, 0.0);
  pressure_.assign(n, 0.0);
  impulse_.assign(n, 0.0);
  gap_.assign(n, 0.0);
  closing_.assign(n, 0);
  count_.assign(n, 0.0);
  pressed_.assign(n * classes(), 0.0);
  fresh_.assign(classes(), 0.0);
  pressed_out_.assign(classes(), 0.0);
  total_.assign(n, 0.0);
  memory_.assign(n, mbd::BedCell{});
  loose_rho_.assign(n, rho0_);
  s_max_.assign(n, m.max_compression);
  mixed_.assign(n, 0);
  if (m.packing_index > 0) {
    std::vector<double> sizes, lower, upper;
    for (std::size_t j = 0; j < classes(); ++j)
      sizes.push_back(breakage_.size(j)), lower.push_back(breakage_.lower(j)), upper.push_back(breakage_.upper(j));
    const std::vector<double> ref = even_size_mixture(lower, upper, m.packing_ref_min_m, m.packing_ref_max_m);
    packing_ = std::make_shared<const MixturePacking>(
        sizes, MixturePacking::beta_for(sizes, m.packing_index, ref, m.loose_fraction), m.packing_index);
  }
  bed_.assign(n, mbd::CompactedBed{});
  refill_.assign(n, BedRefill{});
  out_.assign(classes(), 0.0);
  pass_.assign(classes(), 0.0);
  scratch_.assign(classes(), 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d x = cell_point(k);
    cx_.push_back(x.x()), cy_.push_back(x.y()), cz_.push_back(x.z());
  }
  for (auto* v : {&xm_x_, &xm_y_, &xm_z_, &rho_, &dist_}) v->assign(n, 0.0);
  seg_.assign(n, 0);
}

// Each cell's concave point in the mantle's liner frame, its distance to the mantle's axis and its signed distance to
// the mantle's profile: one pass over all cells, which vectorises (the cell loop of step() reads them).
void FlowModel::locate_cells(const Eigen::Isometry3d& T) {
  const std::size_t n = cells();
  to_frame(T, n, cx_.data(), cy_.data(), cz_.data(), xm_x_.data(), xm_y_.data(), xm_z_.data(), rho_.data());
  mantle_.signed_distances(n, xm_z_.data(), rho_.data(), dist_.data(), seg_.data());
}

Eigen::Vector3d FlowModel::cell_point(std::size_t k) const {
  return cells_.point(k / p_.sectors, k % p_.sectors);
}

// The cells whose rock changed since: the loose density of their mixture and their compaction limit (the solid's),
// solved from the cell's last; an empty cell takes the reference bed's.
void FlowModel::refresh_packing() {
  if (!packing_) return;
  const auto& m = p_.material;
  for (std::size_t k = 0; k < cells(); ++k) {
    if (total_[k] <= 0) {
      loose_rho_[k] = rho0_, s_max_[k] = m.max_compression, mixed_[k] = 0;
      continue;
    }
    if (!mixed_[k]) continue;
    mixed_[k] = 0;
    const double phi = packing_->fraction(&mass_[k * classes()], loose_rho_[k] / m.solid_density);
    loose_rho_[k] = phi * m.solid_density;
    s_max_[k] = std::min(m.max_compression, solid_compaction_limit(phi));
  }
}

// The locked layer's stiffness at cell k's compaction limit (bed_limit.hpp).
double FlowModel::locked_stiffness(std::size_t k) const {
  if (!packing_) return locked_stiffness_;
  const auto& m = p_.material;
  return locked_bed_stiffness(m.exponent, m.rebound, s_max_[k], m.modulus_Pa * std::pow(s_max_[k], m.exponent));
}

double FlowModel::sum_classes(std::size_t k) const {
  const auto* m = &mass_[k * classes()];
  return std::accumulate(m, m + classes(), 0.0);
}

// Loose mass that fills the space cell k's rock takes: compacted rock, released, takes m (1 - er) / rho0 of it, er the
// compaction the bed law releases it at (mbd::released_compaction, (1 - rebound) c).
double FlowModel::loose_volume_mass(std::size_t k) const {
  return p_.compaction_memory ? total_[k] * (1.0 - mbd::released_compaction(bed_[k], p_.material.rebound)) : total_[k];
}

double FlowModel::mass_kg() const { return std::accumulate(mass_.begin(), mass_.end(), 0.0); }
double FlowModel::discharged_kg() const { return std::accumulate(out_.begin(), out_.end(), 0.0); }
double FlowModel::product_compressions() const {
  const double m = discharged_kg();
  return m > 0 ? out_count_ / m : 0.0;
}

std::vector<double> FlowModel::passing(const std::vector<double>& by_class) const {
  const double total = std::accumulate(by_class.begin(), by_class.end(), 0.0);
  std::vector<double> out;
  double cum = 0;
  for (std::size_t k = 0; k < p_.sieves_m.size(); ++k) {
    cum += by_class[k];
    out.push_back(total > 0 ? cum / total : 0.0);
  }
  return out;
}

void FlowModel::deposit(std::size_t k, const std::vector<double>& class_kg) {
  if (k >= cells() || class_kg.size() != classes())
    throw std::invalid_argument("FlowModel::deposit: cell or number of size classes out of range");
  for (double kg : class_kg)
    if (!(kg >= 0) || !std::isfinite(kg))
      throw std::invalid_argument("FlowModel::deposit: masses must be finite and >= 0");
  add(k, class_kg.data(), 1.0, false);
}

// Choke feed: the hopper's column rests on the top band's rock and moves with it (keeps the cell's speed).
void FlowModel::fill(std::size_t k, double kg) { add(k, feed_share_.data(), kg, true); }

// Adds scale x share[j] kg per class to cell k: fresh rock, no compressions yet; at rest unless keep_speed.
void FlowModel::add(std::size_t k, const double* share, double scale, bool keep_speed) {
  double* c = &mass_[k * classes()];
  const double m = cell_mass(k);
  double kg = 0;
  for (std::size_t j = 0; j < classes(); ++j) c[j] += scale * share[j], kg += scale * share[j];
  total_[k] = sum_classes(k);
  mixed_[k] = 1;
  mbd::mix_compaction(bed_[k], m, kg, 0.0);  // fresh rock is loose
  if (m + kg > 0) {
    count_[k] *= m / (m + kg);
    if (!keep_speed) speed_[k] *= m / (m + kg);
  }
  fed_ += kg;
}

// Moves kg of cell `from`'s rock, split by class_share (sums to 1 over the classes), into `to` (kg per class);
// to_count receives kg x the cell's compression count.
void FlowModel::move(std::size_t from, double* to, double kg, const double* class_share, double* to_count) {
  double* f = &mass_[from * classes()];
  double left = 0;  // sum_classes(from) after the move, summed as it goes
  for (std::size_t j = 0; j < classes(); ++j) {
    const double d = std::min(f[j], kg * class_share[j]);
    f[j] -= d;
    to[j] += d;
    left += f[j];
  }
  total_[from] = left;
  mixed_[from] = 1;
  *to_count += kg * count_[from];
}

// One pressing from s0 to s1 breaks the rock f (kg per class) but the part `pressed` (kg per class, in f) that has had
// it already; returns the share of f's mass it broke (1 when none had it).
double FlowModel::break_fresh(double* f, const double* pressed, double s0, double s1) {
  const std::size_t C = classes();
  double all = 0, had = 0;
  for (std::size_t j = 0; j < C; ++j) all += f[j], had += pressed[j];
  if (had <= 0) {  // (bit for bit as before this law where no rock was pressed out)
    breakage_.apply_between(s0, s1, f);
    return 1.0;
  }
  for (std::size_t j = 0; j < C; ++j) fresh_[j] = std::max(0.0, f[j] - pressed[j]);
  breakage_.apply_between(s0, s1, fresh_.data());
  for (std::size_t j = 0; j < C; ++j) f[j] = fresh_[j] + pressed[j];
  return all > 0 ? std::max(0.0, 1.0 - had / all) : 0.0;
}

FlowLoads FlowModel::step(const Eigen::Isometry3d& mantle, const Eigen::Isometry3d& concave,
                          const Eigen::Vector3d& com_m, const Eigen::Vector3d& com_c, double h, double gravity,
                          const LinerTwists* twists) {
  FlowLoads out;
  const LinerFriction& lf = p_.effects.liner_friction;
  const LinerTwists* slip = lf.enabled ? twists : nullptr;
  const Eigen::Isometry3d to_mantle = mantle.inverse(), concave_to_mantle = to_mantle * concave;
  const std::size_t S = static_cast<std::size_t>(p_.sectors), C = classes();
  const auto& mat = p_.material;
  const CompactionScale scale = compaction_scale(mat);  // the pressure law's coordinate u(s); its memory holds u
  // Puts rock taken from cell k (kg per class in scratch_, kg x its compressions in kg_count) into the cell below, or
  // out of the chamber from the bottom band; c_moved: the compaction it keeps (0: it falls and is re-poured).
  // pressed_out: the rock was pressed out of cell k's nip (it has had the pressing it joins below, if one goes on).
  auto deliver = [&](std::size_t k, double kg, double kg_count, double c_moved, bool pressed_out) {
    if (k < S) {
      for (std::size_t j = 0; j < C; ++j) out_[j] += scratch_[j];
      out_count_ += kg_count;
      if (pressed_out) extruded_out_ += kg, extruded_gap_ += kg * gap_[k];
      return;
    }
    const std::size_t below = k - S;
    const double mb = total_[below];
    mbd::mix_compaction(bed_[below], mb, kg, c_moved);
    double sum = 0;  // sum_classes(below) after the delivery, summed as it goes
    for (std::size_t j = 0; j < C; ++j) sum += (mass_[below * C + j] += scratch_[j]);
    total_[below] = sum;
    mixed_[below] = 1;
    count_[below] = (mb * count_[below] + kg_count) / (mb + kg);
    if (pressed_out)  // it has had the pressing it joins below (its cycle's), until that cell releases its rock
      for (std::size_t j = 0; j < C; ++j) pressed_[below * C + j] += scratch_[j];
    speed_[below] = (mb * speed_[below] + kg * speed_[k]) / (mb + kg);
  };
  // Free rock falls: kg out of cell k, split by share, into the cell below (out from the bottom band), re-poured.
  auto send_down = [&](std::size_t k, double kg, const double* share) {
    if (kg <= 0) return;
    std::fill(scratch_.begin(), scratch_.end(), 0.0);
    double moved_count = 0;
    move(k, scratch_.data(), kg, share, &moved_count);
    deliver(k, kg, moved_count, 0.0, false);
  };
  // Rock pressed past the compaction limit: kg of cell k's rock (in proportion to its classes) is broken as by one
  // event from where its pressing started to the limit, then pushed into the cell below (out from the bottom band),
  // keeping the limit's compaction (compaction_memory) and counting the event. Rock pressed out into k by this same
  // pressing (pressed_) has had it: one pressing breaks a lump once, however many bands it flows through.
  auto extrude = [&](std::size_t k, double kg) {
    double* f = &mass_[k * C];
    double* pressed = &pressed_[k * C];
    const double share = kg / total_[k];
    for (std::size_t j = 0; j < C; ++j) {
      scratch_[j] = f[j] * share;
      f[j] -= scratch_[j];
      pressed_out_[j] = pressed[j] * share;
      pressed[j] -= pressed_out_[j];
    }
    total_[k] = sum_classes(k);
    mixed_[k] = 1;
    const double s_max = s_max_[k];
    double D, fresh;
    if (p_.compaction_memory) {
      const double from = bed_[k].pressed ? bed_[k].c_start : bed_[k].c;
      D = s_max - from;
      fresh = break_fresh(scratch_.data(), pressed_out_.data(), from, s_max);
    } else {
      const double e0 = std::min(scale.s(memory_[k].e0), s_max);
      D = s_max - e0;
      fresh = break_fresh(scratch_.data(), pressed_out_.data(), 0.0, D / (1.0 - e0));
    }
    deliver(k, kg, kg * (count_[k] + (D >= kCountedCompression ? fresh : 0.0)), s_max, true);
  };
  locate_cells(concave_to_mantle);
  refresh_packing();
  for (std::size_t k = 0; k < cells(); ++k) {
    const std::size_t b = k / S;
    // The cell's point on the concave, its gap to the mantle along the mantle's normal there.
    const Eigen::Vector3d xc(cx_[k], cy_[k], cz_[k]);
    const Eigen::Vector3d xm(xm_x_[k], xm_y_[k], xm_z_[k]);
    const double rho = rho_[k];
    const Eigen::Vector2d nzr = mantle_.normal_zr(seg_[k]);
    const double g = std::max(0.0, -dist_[k]);
    const double g_before = gap_[k], p_before = pressure_[k];
    closing_[k] = prefilled_ && g < g_before;  // Evertsson: rock is held while the gap closes on it
    gap_[k] = g;
    pressure_[k] = 0;
    const double cap = cells_.area[b] * g * loose_rho_[k];  // loose mass the cell's space holds
    if (!prefilled_ && p_.prefill) fill(k, cap);
    double m = total_[k];
    // Compaction limit: rock pressed past max_compression flows out of the nip into the cell below, broken as by the
    // pressing that took it to the limit (the event the rock left behind completes later with the same ratio).
    const bool loose = m <= cap;  // within its loose room: no compaction, below the limit (cap <= cap / (1 - s_max))
    const double m_max = loose ? cap : cap / (1.0 - s_max_[k]);
    const bool extruded = m > m_max && !mat.elastic_limit;
    const double locked_strain = m > m_max && mat.elastic_limit ? 1.0 - m_max / m : 0.0;  // bed_limit.hpp
    if (extruded) {
      extrude(k, m - m_max);
      m = m_max;
    }
    const double squeeze = extruded && p_.effects.squeeze_flow.enabled  // pressed out against the liners' friction
                               ? squeeze_flow_factor(p_.effects.squeeze_flow.wall_friction,
                                                     p_.effects.squeeze_flow.escape_length_m, g)
                               : 1.0;
    // The crushing work is the liners' work on the rock, p A dg over the step (trapezoid): over a loop the hysteretic
    // law's loss (1 - rebound) E D^(n+1) / (n + 1) per loose volume, plus, at the compaction limit, the work of
    // pressing rock out of the nip.
    auto book_work = [&](double p) {
      if (!prefilled_) return;
      const double dW = 0.5 * (p_before + p) * cells_.area[b] * (g_before - g);
      energy_ += dW;
      if (extruded) extrusion_ += dW;
    };
    if (m <= 0) {  // emptied (the gap closed to nothing): the last of the liners' work on it is booked
      book_work(0.0);
      memory_[k] = mbd::BedCell{};
      bed_[k] = mbd::CompactedBed{};
      refill_[k] = BedRefill{};
      std::fill_n(&pressed_[k * C], C, 0.0);
      continue;
    }
    double e = loose ? 0.0 : std::clamp(1.0 - cap / m, 0.0, s_max_[k]);
    if (e < 1e-9) e = 0;  // a cell filled to its loose capacity carries no load (round-off would hold it)
    // A compression event ends when the liner leaves the rock. With memory it took the rock from the compaction it had
    // (c_start) on to c and selects by the hazard's rise between them (a reload within c breaks nothing); without,
    // by its ratio D / (1 - s0) from where it started.
    double p = 0, D = 0, fresh = 1.0;
    if (p_.compaction_memory) {
      const mbd::CompactedBed before = bed_[k];
      p = mbd::bed_compacted(bed_[k], e, mat.modulus_Pa, mat.exponent, mat.rebound).p;
      if (before.pressed && !bed_[k].pressed && before.c > before.c_start) {
        D = before.c - before.c_start;
        fresh = break_fresh(&mass_[k * C], &pressed_[k * C], before.c_start, before.c);
      }
    } else {
      const mbd::BedCell before = memory_[k];
      p = bed_refilling(memory_[k], refill_[k], scale.u(e), h, mat.modulus_Pa, mat.exponent, mat.rebound,
                        mat.refill_length_m, gravity).p;
      if (mbd::bed_loop_ended(before, memory_[k])) {
        const double s0 = scale.s(before.e0);
        D = scale.s(before.emax) - s0;
        fresh = break_fresh(&mass_[k * C], &pressed_[k * C], 0.0, D / (1.0 - s0));
      }
    }
    p += locked_bed_pressure(locked_strain, locked_strain > 0 ? locked_stiffness(k) : 0.0);
    p *= squeeze;
    if (mat.lump_std > 0) {  // a new pressing meets its rock as it lies now: its own strength
      if (p_before <= 0 && p > 0)
        scatter_[k] = draws_.factor(bed_pressure_std(mat.lump_std, effective_lumps(&mass_[k * C], lump_kg_)));
      p *= scatter_[k];
    }
    if (D > 0) {
      total_[k] = sum_classes(k);
      mixed_[k] = 1;
      if (D >= kCountedCompression) count_[k] += fresh, ++events_;
    }
    pressure_[k] = p;
    if (D > 0) std::fill_n(&pressed_[k * C], C, 0.0);  // its pressing ended: the next is new to all
    book_work(p);
    if (p <= 0) continue;
    impulse_[k] += p * cells_.area[b] * h;
    const double inv = 1.0 / std::max(rho, 1e-12);
    const Eigen::Vector3d n =
        mantle.linear() * Eigen::Vector3d(nzr.y() * xm.x() * inv, nzr.y() * xm.y() * inv, nzr.x());
    const Eigen::Vector3d X = concave * xc;
    const Eigen::Vector3d F = p * cells_.area[b] * n;  // on the concave (n: out of the mantle); -F on the mantle
    out.f_concave += F;
    out.t_concave += (X - com_c).cross(F);
    out.f_mantle -= F;
    out.t_mantle += (X - g * n - com_m).cross(-F);
    out.normal_force += p * cells_.area[b];
    if (slip) {  // the rock's friction against the mantle's slip, at the middle of the gap
      const Eigen::Vector3d Xm = X - 0.5 * g * n, v_t = liner_slip(*slip, Xm, n, com_m, com_c);
      const Eigen::Vector3d Ff = liner_friction_force(lf, p * cells_.area[b], v_t);
      out.f_mantle += Ff;
      out.t_mantle += (Xm - com_m).cross(Ff);
      out.f_concave -= Ff;
      out.t_concave += (Xm - com_c).cross(-Ff);
      friction_ -= Ff.dot(v_t) * h;
    }
  }
  // Rock at the compaction limit does not compact further: what was pressed into a cell below that this step had left at
  // its limit goes on down in the same step, as far as a cell with room (or out), not one band per step.
  for (std::size_t k = mat.elastic_limit ? 0 : cells(); k-- > 0;) {  // (held rock is not pressed out)
    const double over = total_[k] - cells_.area[k / S] * gap_[k] * loose_rho_[k] / (1.0 - s_max_[k]);
    if (over > 1e-12 * total_[k]) extrude(k, over);
  }
  prefilled_ = true;
  // Free rock falls, bottom band first (what leaves a cell makes room above it in the same step).
  for (std::size_t k = 0; k < cells(); ++k) {
    const std::size_t b = k / S;
    const double m = total_[k];
    if (m <= 0 || pressure_[k] > 0 || closing_[k]) {
      speed_[k] = 0;
      continue;
    }
    std::fill_n(&pressed_[k * C], C, 0.0);  // released: its next pressing is new to all its rock
    speed_[k] += gravity * h;
    const double g_next = b > 0 ? gap_[k - S] : gap_[k];
    const double* f = &mass_[k * C];
    // What of each class passes the gap below (classes ascend: the fine ones wholly, one in part, the rest not;
    // summed in class order as passes() x f would, the zeros left out)
    double movable = 0;
    std::size_t j = 0;
    for (; j < C && breakage_.upper(j) <= g_next; ++j) pass_[j] = f[j], movable += f[j];
    for (; j < C && breakage_.lower(j) < g_next; ++j) {
      pass_[j] = passes(breakage_.lower(j), breakage_.upper(j), g_next) * f[j];
      movable += pass_[j];
    }
    std::fill(pass_.begin() + j, pass_.end(), 0.0);
    double kg = movable * std::min(1.0, speed_[k] * h / cells_.dz);
    if (b > 0) {
      const double room = std::max(0.0, loose_rho_[k - S] * cells_.area[b - 1] * gap_[k - S] - loose_volume_mass(k - S));
      if (kg > room) kg = room, speed_[k] = std::min(speed_[k], speed_[k - S]);  // resting on the rock below
    }
    if (kg <= 0) {
      if (movable <= 0) speed_[k] = 0;  // nothing fits through the gap below: the lumps are held
      continue;
    }
    for (std::size_t j = 0; j < C; ++j) pass_[j] /= movable;
    send_down(k, kg, pass_.data());
  }
  // Choke feed into the free cells of the top band; a limited feed shares its rate h over their room.
  if (p_.choke_feed) {
    double share = 1.0;
    if (p_.effects.feed_limited.enabled) {
      double room = 0;
      for (std::size_t k = cells() - S; k < cells(); ++k)
        if (pressure_[k] <= 0) room += std::max(0.0, loose_rho_[k] * cells_.area[k / S] * gap_[k] - loose_volume_mass(k));
      const double budget = p_.effects.feed_limited.max_feed_kg_s * h;
      if (room > budget) share = budget / room;
    }
    for (std::size_t k = cells() - S; k < cells(); ++k) {
      if (pressure_[k] > 0) continue;
      const double room = loose_rho_[k] * cells_.area[k / S] * gap_[k] - loose_volume_mass(k);
      if (room > 0) fill(k, room * share);
    }
  }
  return out;
}

std::vector<double> material_fingerprint(const FlowMaterial& m) {
  const auto& b = m.breakage;
  return {m.solid_density, m.loose_fraction, m.modulus_Pa, m.exponent, m.rebound, m.max_compression, b.s_c, b.m, b.q,
          b.x_ref, b.x_resolved, b.q_below, b.phi, b.gamma, b.beta};
}

std::vector<double> law_fingerprint(const FlowMaterial& m) {
  std::vector<double> f;
  if (m.solid_divergence) f.push_back(-2.0);
  if (m.elastic_limit) f.push_back(-4.0);
  if (m.refill_length_m > 0) f.insert(f.end(), {-6.0, m.refill_length_m});
  if (m.packing_index > 0) f.insert(f.end(), {-7.0, m.packing_index, m.packing_ref_min_m, m.packing_ref_max_m});
  return f;
}

// The parameters a state belongs to, bit for bit: sieves, feed, material, breakage and the switches.
std::vector<double> FlowModel::fingerprint() const {
  const auto& m = p_.material;
  std::vector<double> f = p_.sieves_m;
  f.insert(f.end(), p_.feed_passing.begin(), p_.feed_passing.end());
  const std::vector<double> rock = material_fingerprint(m), laws = law_fingerprint(m);
  f.insert(f.end(), rock.begin(), rock.end());
  f.insert(f.end(), {double(p_.prefill), double(p_.choke_feed), double(p_.compaction_memory)});
  if (m.lump_std > 0) f.insert(f.end(), {m.lump_std, double(p_.seed)});  // (without: as before the scatter)
  f.insert(f.end(), laws.begin(), laws.end());
  const auto& lf = p_.effects.liner_friction;
  if (lf.enabled) f.insert(f.end(), {-3.0, lf.wall_friction, lf.regularisation_m_s});  // (without: as before it)
  return f;
}

void FlowModel::save_state(core::BinaryWriter& w) const {
  w.tag("FLOW");
  w.put<int64_t>(p_.bands);
  w.put<int64_t>(p_.sectors);
  w.put<int64_t>(static_cast<int64_t>(classes()));
  w.put_vec(fingerprint());
  w.put_vec(mass_);
  w.put_vec(speed_);
  w.put_vec(count_);
  std::vector<double> mem;
  for (std::size_t k = 0; k < memory_.size(); ++k)
    mem.insert(mem.end(), {memory_[k].e0, memory_[k].emax, bed_[k].c, bed_[k].c_start, double(bed_[k].pressed)});
  w.put_vec(mem);
  w.put_vec(out_);
  w.put_vec(gap_);
  w.put_vec(pressure_);
  w.put_vec(impulse_);
  w.put(fed_);
  w.put(energy_);
  w.put(extrusion_);
  w.put(out_count_);
  w.put<int64_t>(events_);
  w.put<char>(prefilled_);
  w.put_vec(taken_);
  w.tag("PRSD");  // the rock pressed out into each cell's ongoing pressing (a file without it: another version)
  w.put_vec(pressed_);
  if (p_.material.lump_std > 0) {
    w.tag("SCAT");
    w.put_vec(scatter_);
    w.put_string(draws_.state());
  }
  if (p_.effects.liner_friction.enabled) {
    w.tag("FRIC");
    w.put(friction_);
  }
  w.tag("EXTD");  // the discharge pressed out of the nip (a file without it: another version)
  w.put(extruded_out_);
  w.put(extruded_gap_);
  if (p_.material.refill_length_m > 0) {
    w.tag("RFIL");
    std::vector<double> rf;
    for (const BedRefill& r : refill_) rf.insert(rf.end(), {double(r.open), r.released, r.low, r.t});
    w.put_vec(rf);
  }
  if (packing_) {  // (each cell's is solved from its last, so it is state)
    w.tag("PACK");
    w.put_vec(loose_rho_);
    w.put_vec(s_max_);
    w.put_vec(std::vector<double>(mixed_.begin(), mixed_.end()));
  }
}

void FlowModel::load_state(core::BinaryReader& r) {
  r.expect("FLOW");
  if (r.get<int64_t>() != p_.bands || r.get<int64_t>() != p_.sectors ||
      r.get<int64_t>() != static_cast<int64_t>(classes()))
    r.fail("flow model cells or size classes differ");
  std::vector<double> fp;
  r.get_vec(fp);
  if (fp != fingerprint())
    r.fail("the flow model's parameters differ from the checkpoint's (flow: sieves, feed, material, breakage or "
           "switches; resume with the run's config)");
  const std::size_t n = cells();
  std::vector<double> mass, speed, count, mem, out;
  r.get_vec(mass);
  r.get_vec(speed);
  r.get_vec(count);
  r.get_vec(mem);
  r.get_vec(out);
  std::vector<double> gap, pressure, impulse;
  r.get_vec(gap);
  r.get_vec(pressure);
  r.get_vec(impulse);
  if (mass.size() != n * classes() || speed.size() != n || count.size() != n || mem.size() != 5 * n ||
      out.size() != classes() || gap.size() != n || pressure.size() != n || impulse.size() != n)
    r.fail("flow model state is corrupt");
  mass_ = mass, speed_ = speed, count_ = count, out_ = out, gap_ = gap, pressure_ = pressure, impulse_ = impulse;
  for (std::size_t k = 0; k < n; ++k) {
    const double* q = &mem[5 * k];
    memory_[k] = {q[0], q[1]};
    bed_[k] = {q[2], q[3], q[4] != 0};
    total_[k] = sum_classes(k);
  }
  r.get(fed_);
  r.get(energy_);
  r.get(extrusion_);
  r.get(out_count_);
  events_ = static_cast<long>(r.get<int64_t>());
  prefilled_ = r.get<char>() != 0;
  r.get_vec(taken_);
  if (!taken_.empty() && taken_.size() != classes()) r.fail("flow model state is corrupt");
  r.expect("PRSD");
  r.get_vec(pressed_);
  if (pressed_.size() != n * classes()) r.fail("flow model state is corrupt");
  if (p_.material.lump_std > 0) {
    r.expect("SCAT");
    std::vector<double> scatter;
    r.get_vec(scatter);
    if (scatter.size() != n || !draws_.set_state(r.get_string())) r.fail("flow model state is corrupt");
    scatter_ = scatter;
  }
  if (p_.effects.liner_friction.enabled) {
    r.expect("FRIC");
    r.get(friction_);
  }
  r.expect("EXTD");
  r.get(extruded_out_);
  r.get(extruded_gap_);
  if (p_.material.refill_length_m > 0) {
    r.expect("RFIL");
    std::vector<double> rf;
    r.get_vec(rf);
    if (rf.size() != 4 * n) r.fail("flow model state is corrupt");
    for (std::size_t k = 0; k < n; ++k) refill_[k] = {rf[4 * k] != 0, rf[4 * k + 1], rf[4 * k + 2], rf[4 * k + 3]};
  }
  if (packing_) {
    r.expect("PACK");
    std::vector<double> rho, s_max, mixed;
    r.get_vec(rho);
    r.get_vec(s_max);
    r.get_vec(mixed);
    if (rho.size() != n || s_max.size() != n || mixed.size() != n) r.fail("flow model state is corrupt");
    loose_rho_ = rho, s_max_ = s_max;
    for (std::size_t k = 0; k < n; ++k) mixed_[k] = mixed[k] != 0;
  }
}

}  // namespace chamber
