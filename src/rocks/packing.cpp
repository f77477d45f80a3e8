#include "rocks/packing.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "core/units.hpp"

namespace rocks {

double RockPacking::solid_volume() const {
  double v = 0.0;
  for (double r : radii) v += r * r * r;
  return 4.0 / 3.0 * core::units::kPi * v;
}

std::vector<std::pair<int, int>> near_pairs(const std::vector<Vec3>& x, const std::vector<double>& r,
                                            double inflate, double extra) {
  std::vector<std::pair<int, int>> out;
  const int n = static_cast<int>(x.size());
  if (n < 2) return out;
  double rmax = 0.0;
  Vec3 lo = Vec3::Constant(1e300);
  for (int i = 0; i < n; ++i) {
    rmax = std::max(rmax, r[i]);
    lo = lo.cwiseMin(x[i]);
  }
  const double cell = 2.0 * rmax * inflate + extra;
  auto key = [&](const Vec3& p, int& a, int& b, int& c) {
    a = static_cast<int>(std::floor((p.x() - lo.x()) / cell));
    b = static_cast<int>(std::floor((p.y() - lo.y()) / cell));
    c = static_cast<int>(std::floor((p.z() - lo.z()) / cell));
  };
  auto hash = [](int a, int b, int c) {
    return (static_cast<long long>(a) << 42) ^ (static_cast<long long>(b) << 21) ^ static_cast<long long>(c);
  };
  std::unordered_map<long long, std::vector<int>> grid;
  grid.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    int a, b, c;
    key(x[i], a, b, c);
    grid[hash(a, b, c)].push_back(i);
  }
  for (int i = 0; i < n; ++i) {
    int a, b, c;
    key(x[i], a, b, c);
    for (int da = -1; da <= 1; ++da)
      for (int db = -1; db <= 1; ++db)
        for (int dc = -1; dc <= 1; ++dc) {
          auto it = grid.find(hash(a + da, b + db, c + dc));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            if (j <= i) continue;
            const double reach = (r[i] + r[j]) * inflate + extra;
            if ((x[j] - x[i]).squaredNorm() < reach * reach) out.emplace_back(i, j);
          }
        }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<int, int>> bond_neighbours(const std::vector<Vec3>& x, const std::vector<double>& r,
                                                 double gap_ratio) {
  if (!(gap_ratio >= 0.0 && gap_ratio <= 1.0))
    throw std::invalid_argument("bond_neighbours: gap_ratio must be in [0, 1]");
  double rmin = 1e300;
  for (double v : r) rmin = std::min(rmin, v);
  std::vector<std::pair<int, int>> out;
  double rmax = 0.0;
  for (double v : r) rmax = std::max(rmax, v);
  for (const auto& p : near_pairs(x, r, 1.0, gap_ratio * rmax)) {
    const int i = p.first, j = p.second;
    const double gap = (x[j] - x[i]).norm() - r[i] - r[j];
    if (gap <= gap_ratio * std::min(r[i], r[j])) out.push_back(p);
  }
  return out;
}

std::pair<double, double> overlap_stats(const std::vector<Vec3>& x, const std::vector<double>& r) {
  double mx = 0.0, sum = 0.0;
  int cnt = 0;
  for (const auto& p : near_pairs(x, r, 1.0, 0.0)) {
    const int i = p.first, j = p.second;
    const double ov = r[i] + r[j] - (x[j] - x[i]).norm();
    if (ov <= 0.0) continue;
    const double rel = ov / std::min(r[i], r[j]);
    mx = std::max(mx, rel);
    sum += rel;
    ++cnt;
  }
  return {mx, cnt ? sum / cnt : 0.0};
}

namespace {
// One Jacobi sweep at radius scale s over candidate pairs; returns max overlap / smaller radius.
double relax_sweep(std::vector<Vec3>& x, const std::vector<double>& r, double s,
                   const std::vector<std::pair<int, int>>& pairs, std::vector<Vec3>& disp, const Shape& shape) {
  std::fill(disp.begin(), disp.end(), Vec3::Zero());
  double worst = 0.0;
  for (const auto& p : pairs) {
    const int i = p.first, j = p.second;
    Vec3 d = x[j] - x[i];
    double dist = d.norm();
    const double ov = s * (r[i] + r[j]) - dist;
    if (ov <= 0.0) continue;
    worst = std::max(worst, ov / (s * std::min(r[i], r[j])));
    Vec3 nrm = dist > 1e-15 ? Vec3(d / dist) : Vec3(1.0, 0.0, 0.0);
    const double vi = r[i] * r[i] * r[i], vj = r[j] * r[j] * r[j];
    const double wi = vj / (vi + vj);  // the smaller sphere moves more
    const double push = 0.6 * ov;      // under-relaxed: many partners push at once
    disp[i] -= push * wi * nrm;
    disp[j] += push * (1.0 - wi) * nrm;
  }
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = shape.push_inside(x[i] + disp[i], s * r[i]);
  return worst;
}
}  // namespace

RockPacking pack_shape(const Shape& shape, const SizeDistribution& dist, const PackingOptions& o) {
  if (!(o.density > 0.05 && o.density < 0.74))
    throw std::invalid_argument("pack_shape: density must be in (0.05, 0.74) (random packings of spheres)");
  if (!(o.overlap_tol > 0.0 && o.overlap_tol < 0.5)) throw std::invalid_argument("pack_shape: overlap_tol in (0, 0.5)");
  const double vol = shape.volume();
  const Vec3 lo = shape.min_corner(), hi = shape.max_corner();
  const double min_extent = (hi - lo).minCoeff();
  if (2.0 * dist.max_radius() > min_extent)
    throw std::invalid_argument("pack_shape: metaparticles (max radius " + std::to_string(dist.max_radius()) +
                                " m) too large for shape '" + shape.name() + "'");
  Rng rng(o.seed);
  RockPacking out;
  out.name = shape.name();
  out.radii = dist.sample_volume(o.density * vol, rng);
  const auto& r = out.radii;
  const int n = static_cast<int>(r.size());
  if (n > 2000000) throw std::invalid_argument("pack_shape: more than 2e6 particles; choose coarser metaparticles");
  double s = std::cbrt(0.25 / o.density);
  auto& x = out.positions;
  x.resize(n);
  for (int i = 0; i < n; ++i) {
    for (int attempt = 0;; ++attempt) {
      const Vec3 p(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()), rng.uniform(lo.z(), hi.z()));
      if (shape.clearance(p) >= s * r[i] || attempt > 10000) {
        x[i] = shape.push_inside(p, s * r[i]);
        break;
      }
    }
  }
  std::vector<Vec3> disp(n), at_build;
  std::vector<std::pair<int, int>> pairs;
  double rmin = 1e300;
  for (double v : r) rmin = std::min(rmin, v);
  const double skin = 0.3 * rmin;
  auto rebuild_if_needed = [&](bool force) {
    double moved = 0.0;
    if (!force)
      for (int i = 0; i < n; ++i) moved = std::max(moved, (x[i] - at_build[i]).squaredNorm());
    if (force || std::sqrt(moved) > 0.5 * skin) {
      pairs = near_pairs(x, r, s, skin);
      at_build = x;
    }
  };
  int sweeps = 0;
  // growth: each stage relaxes until the overlap is modest, then inflates by 0.3 %
  while (s < 1.0) {
    s = std::min(1.0, s * 1.003);
    rebuild_if_needed(true);
    for (int k = 0; k < 40; ++k) {
      rebuild_if_needed(false);
      ++sweeps;
      if (relax_sweep(x, r, s, pairs, disp, shape) < 0.03) break;
    }
  }
  double worst = 1.0;
  rebuild_if_needed(true);
  for (int k = 0; k < o.max_final_sweeps; ++k) {
    rebuild_if_needed(false);
    ++sweeps;
    worst = relax_sweep(x, r, 1.0, pairs, disp, shape);
    if (worst < o.overlap_tol) break;
  }
  const auto st = overlap_stats(x, r);
  out.max_overlap_ratio = st.first;
  out.mean_overlap_ratio = st.second;
  out.sweeps = sweeps;
  if (st.first > o.max_overlap_accept)
    throw std::runtime_error("pack_shape: '" + shape.name() + "' at density " + std::to_string(o.density) +
                             " keeps a max overlap of " + std::to_string(st.first) +
                             " x smaller radius (accepted <= " + std::to_string(o.max_overlap_accept) +
                             "); lower the density");
  out.container_volume = vol;
  out.target_density = o.density;
  out.seed = o.seed;
  out.bond_gap_ratio = o.bond_gap_ratio;
  out.distribution = dist.describe();
  out.bonds = bond_neighbours(x, r, o.bond_gap_ratio);
  keep_largest_cluster(out);
  return out;
}

void keep_largest_cluster(RockPacking& rock) {
  const int n = static_cast<int>(rock.size());
  std::vector<int> parent(n);
  for (int i = 0; i < n; ++i) parent[i] = i;
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& b : rock.bonds) {
    const int a = find(b.first), c = find(b.second);
    if (a != c) parent[std::max(a, c)] = std::min(a, c);
  }
  std::vector<int> size(n, 0);
  for (int i = 0; i < n; ++i) ++size[find(i)];
  const int root = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  if (size[root] == n) return;
  std::vector<int> map(n, -1);
  int k = 0;
  for (int i = 0; i < n; ++i)
    if (find(i) == root) {
      map[i] = k;
      rock.positions[k] = rock.positions[i];
      rock.radii[k] = rock.radii[i];
      ++k;
    }
  rock.positions.resize(k);
  rock.radii.resize(k);
  std::vector<std::pair<int, int>> bonds;
  for (const auto& b : rock.bonds)
    if (map[b.first] >= 0) bonds.emplace_back(map[b.first], map[b.second]);
  rock.bonds = std::move(bonds);
}

}  // namespace rocks
