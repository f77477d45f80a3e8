// Nelder-Mead against a closed-form minimum, and the PSD interpolation used for P80 and the passing figures.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/flow_run.hpp"
#include "analysis/optimise.hpp"

TEST(NelderMead, FindsTheMinimumOfAnAnisotropicQuadratic) {
  int calls = 0;
  auto f = [&](const std::vector<double>& x) {
    ++calls;
    return (x[0] - 1) * (x[0] - 1) + 10 * (x[1] + 2) * (x[1] + 2) + 0.5 * (x[0] - 1) * (x[1] + 2) + 3;
  };
  const auto m = analysis::nelder_mead(f, {0, 0}, {0.5, 0.5}, 1e-12, 500);
  EXPECT_NEAR(m.x[0], 1.0, 1e-4);
  EXPECT_NEAR(m.x[1], -2.0, 1e-4);
  EXPECT_NEAR(m.f, 3.0, 1e-8);
  EXPECT_EQ(m.evaluations, calls);
  EXPECT_LT(m.evaluations, 500);
  EXPECT_THROW(analysis::nelder_mead(f, {0, 0}, {1}, 1e-6), std::invalid_argument);
}

TEST(PassingSize, InterpolatesLinearlyInLogSize) {
  const std::vector<double> x{1, 2, 4, 8, 16}, p{5, 20, 50, 90, 100};
  // 80 % lies between 4 mm (50) and 8 mm (90): 3/4 of the way in log size.
  EXPECT_NEAR(analysis::passing_size_mm(x, p, 80), std::exp(std::log(4.0) + 0.75 * std::log(2.0)), 1e-12);
  EXPECT_NEAR(analysis::passing_at_mm(x, p, std::sqrt(8.0)), 35.0, 1e-12);  // halfway between 2 and 4 mm in log
  EXPECT_EQ(analysis::passing_size_mm(x, {0, 1, 2, 3, 4}, 80), -1);          // not reached inside the sieves
}
