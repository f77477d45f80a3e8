#include "chamber/size_classes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chamber {
namespace {

// Class bounds of a sieve list: the pan from 0, the top class to the largest sieve x sqrt 2 (breakage.hpp).
std::vector<double> bounds(const std::vector<double>& sieves) {
  if (sieves.empty()) throw std::invalid_argument("SizeClassMap: needs at least one sieve");
  for (std::size_t i = 0; i < sieves.size(); ++i)
    if (!(sieves[i] > 0) || (i > 0 && sieves[i] <= sieves[i - 1]))
      throw std::invalid_argument("SizeClassMap: sieves must be > 0 and strictly ascending");
  std::vector<double> b{0.0};
  b.insert(b.end(), sieves.begin(), sieves.end());
  b.push_back(sieves.back() * std::sqrt(2.0));
  return b;
}

}  // namespace

SizeClassMap::SizeClassMap(const std::vector<double>& from_sieves, const std::vector<double>& to_sieves) {
  const auto f = bounds(from_sieves), t = bounds(to_sieves);
  n_from_ = f.size() - 1, n_to_ = t.size() - 1;
  w_.assign(n_to_ * n_from_, 0.0);
  for (std::size_t j = 0; j < n_from_; ++j) {
    double sum = 0;
    for (std::size_t i = 0; i < n_to_; ++i)
      sum += (w_[i * n_from_ + j] = std::max(0.0, std::min(f[j + 1], t[i + 1]) - std::max(f[j], t[i])));
    if (sum <= 0) {  // beyond the other set's top class: into it
      w_[(n_to_ - 1) * n_from_ + j] = 1.0;
      continue;
    }
    for (std::size_t i = 0; i < n_to_; ++i) w_[i * n_from_ + j] /= sum;
  }
}

std::vector<double> SizeClassMap::map(const std::vector<double>& from_kg) const {
  if (from_kg.size() != n_from_)
    throw std::invalid_argument("SizeClassMap::map: " + std::to_string(from_kg.size()) + " masses for " +
                                std::to_string(n_from_) + " size classes");
  std::vector<double> out(n_to_, 0.0);
  for (std::size_t j = 0; j < n_from_; ++j) {
    if (from_kg[j] == 0) continue;
    for (std::size_t i = 0; i < n_to_; ++i) out[i] += share(i, j) * from_kg[j];
  }
  return out;
}

}  // namespace chamber
