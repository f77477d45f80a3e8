#pragma once
// Moving masses between two sets of size classes (sieves): a class is the interval between its sieves, the pan
// [0, first sieve], the top class [largest sieve, largest sieve x sqrt 2] (as breakage.hpp bounds them). A class's
// mass goes to the classes of the other set in proportion to the overlap of their intervals (mass taken as uniform
// in size within a class), so every column sums to 1 and mass is conserved; identical sieves give the identity.
// The coupled run's DEM screens on dem.sieves_mm, its fines live in the flow model's flow.sieves_mm classes.
#include <vector>

namespace chamber {

class SizeClassMap {
 public:
  SizeClassMap() = default;
  // from, to: ascending sieves (m); throws std::invalid_argument for an empty or unsorted list.
  SizeClassMap(const std::vector<double>& from_sieves_m, const std::vector<double>& to_sieves_m);
  std::size_t from_classes() const { return n_from_; }
  std::size_t to_classes() const { return n_to_; }
  double share(std::size_t to, std::size_t from) const { return w_[to * n_from_ + from]; }  // of class `from`'s mass
  std::vector<double> map(const std::vector<double>& from_kg) const;  // kg per `to` class; throws on a wrong size

 private:
  std::size_t n_from_ = 0, n_to_ = 0;
  std::vector<double> w_;  // to x from
};

}  // namespace chamber
