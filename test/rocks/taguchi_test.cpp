// Taguchi L16 array, F distribution and ANOVA against published / closed-form values.
#include <gtest/gtest.h>

#include <cmath>

#include "rocks/taguchi.hpp"

using namespace rocks;

TEST(Taguchi, L16IsOrthogonal) {
  const auto& a = l16_array();
  ASSERT_EQ(a.size(), 16u);
  for (const auto& r : a) ASSERT_EQ(r.size(), 5u);
  // every pair of columns holds each of the 16 level pairs exactly once
  for (int c1 = 0; c1 < 5; ++c1)
    for (int c2 = c1 + 1; c2 < 5; ++c2) {
      int count[4][4] = {};
      for (const auto& r : a) ++count[r[c1] - 1][r[c2] - 1];
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_EQ(count[i][j], 1) << "columns " << c1 + 1 << "," << c2 + 1;
    }
  EXPECT_TRUE(is_orthogonal(a, 4));
  auto broken = a;
  std::swap(broken[0][4], broken[1][4]);  // breaks column 5's pairing with the others
  EXPECT_FALSE(is_orthogonal(broken, 4));
}

TEST(Taguchi, IncompleteBetaClosedForm) {
  // I_x(3/2, 3/2) = (2/pi) (asin(sqrt x) - (1 - 2x) sqrt(x (1 - x)))  (integrate (8/pi) sqrt(t(1-t)))
  for (double x : {0.01, 1.0 / 6.0, 0.3, 0.5, 0.77, 0.99}) {
    const double exact = 2.0 / M_PI * (std::asin(std::sqrt(x)) - (1.0 - 2.0 * x) * std::sqrt(x * (1.0 - x)));
    EXPECT_NEAR(incomplete_beta(1.5, 1.5, x), exact, 1e-12) << x;
  }
  // I_x(1, b) = 1 - (1 - x)^b and I_x(a, 1) = x^a
  EXPECT_NEAR(incomplete_beta(1.0, 4.0, 0.2), 1.0 - std::pow(0.8, 4), 1e-13);
  EXPECT_NEAR(incomplete_beta(2.5, 1.0, 0.7), std::pow(0.7, 2.5), 1e-13);
  EXPECT_THROW(incomplete_beta(0.0, 1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(incomplete_beta(1.0, 1.0, 1.5), std::invalid_argument);
}

TEST(Taguchi, FDistributionMatchesTables) {
  // Upper critical values of F (e.g. Montgomery, Design and Analysis of Experiments, App. Table IV):
  // F_0.05(3,16) = 3.24, F_0.01(3,16) = 5.29, F_0.10(3,3) = 5.39, F_0.05(3,3) = 9.28
  EXPECT_NEAR(f_distribution_sf(3.2389, 3, 16), 0.05, 2e-4);
  EXPECT_NEAR(f_distribution_sf(5.2922, 3, 16), 0.01, 1e-4);
  EXPECT_NEAR(f_distribution_sf(5.3908, 3, 3), 0.10, 3e-4);
  EXPECT_NEAR(f_distribution_sf(9.2766, 3, 3), 0.05, 2e-4);
  EXPECT_DOUBLE_EQ(f_distribution_sf(0.0, 3, 3), 1.0);
}

TEST(Taguchi, AnovaReproducesMontgomeryExample3_1) {
  // Montgomery, Design and Analysis of Experiments (8th ed.), Example 3.1, plasma etching: etch rate
  // (A/min) at RF power 160/180/200/220 W, five replicates. Published: SS_Treatments = 66,870.55,
  // SS_E = 5,339.20, SS_T = 72,209.75, MS 22,290.18 and 333.70, F0 = 66.80, P < 0.01.
  const double data[4][5] = {{575, 542, 530, 539, 570},
                             {565, 593, 590, 579, 610},
                             {600, 651, 610, 637, 629},
                             {725, 700, 715, 685, 710}};
  std::vector<std::vector<int>> runs;
  std::vector<double> y;
  for (int l = 0; l < 4; ++l)
    for (int k = 0; k < 5; ++k) {
      runs.push_back({l + 1});
      y.push_back(data[l][k]);
    }
  const AnovaTable t = anova(runs, y, {"RF power"}, {}, 4);
  ASSERT_EQ(t.factors.size(), 1u);
  EXPECT_EQ(t.factors[0].df, 3);
  EXPECT_NEAR(t.factors[0].ss, 66870.55, 0.01);
  EXPECT_NEAR(t.factors[0].ms, 22290.18, 0.01);
  EXPECT_EQ(t.error.df, 16);
  EXPECT_NEAR(t.error.ss, 5339.20, 0.01);
  EXPECT_NEAR(t.error.ms, 333.70, 0.01);
  EXPECT_NEAR(t.total.ss, 72209.75, 0.01);
  EXPECT_NEAR(t.factors[0].F, 66.80, 0.005);
  EXPECT_LT(t.factors[0].p, 1e-7);
  EXPECT_GT(t.factors[0].p, 1e-10);
  EXPECT_NEAR(t.grand_mean, 617.75, 1e-9);
}

TEST(Taguchi, AnovaOnL16HandComputed) {
  // Hand-computed: y = 10 + a[level of col 1] + b[level of col 4] + e[level of col 3] with
  // a = (-3, -1, 1, 3), b = (2, 0, 0, -2), e = (1, -1, 1, -1). Orthogonality makes each SS
  // 4 * sum(effect^2): SS_1 = 80, SS_4 = 32, SS_error(col 3) = 16, SS_2 = SS_5 = 0, SS_T = 128.
  // F_1 = (80/3) / (16/3) = 5, p = I_{1/6}(3/2, 3/2) = 0.10955; F_4 = 2, p = I_{1/3}(3/2, 3/2).
  const double a[4] = {-3, -1, 1, 3}, b[4] = {2, 0, 0, -2}, e[4] = {1, -1, 1, -1};
  std::vector<double> y;
  for (const auto& r : l16_array()) y.push_back(10.0 + a[r[0] - 1] + b[r[3] - 1] + e[r[2] - 1]);
  const AnovaTable t = anova(l16_array(), y, {"A", "B", "err", "D", "E"}, {2}, 4);
  ASSERT_EQ(t.factors.size(), 4u);
  EXPECT_NEAR(t.factors[0].ss, 80.0, 1e-9);
  EXPECT_NEAR(t.factors[1].ss, 0.0, 1e-9);
  EXPECT_NEAR(t.factors[2].ss, 32.0, 1e-9);
  EXPECT_NEAR(t.factors[3].ss, 0.0, 1e-9);
  EXPECT_EQ(t.error.df, 3);
  EXPECT_NEAR(t.error.ss, 16.0, 1e-9);
  EXPECT_NEAR(t.total.ss, 128.0, 1e-9);
  EXPECT_NEAR(t.factors[0].F, 5.0, 1e-12);
  auto i33 = [](double x) {
    return 2.0 / M_PI * (std::asin(std::sqrt(x)) - (1.0 - 2.0 * x) * std::sqrt(x * (1.0 - x)));
  };
  EXPECT_NEAR(t.factors[0].p, i33(1.0 / 6.0), 1e-10);
  EXPECT_NEAR(t.factors[0].p, 0.10955, 1e-5);
  EXPECT_NEAR(t.factors[2].F, 2.0, 1e-12);
  EXPECT_NEAR(t.factors[2].p, i33(1.0 / 3.0), 1e-10);
  const auto mm = marginal_means(l16_array(), y, 4);
  for (int l = 0; l < 4; ++l) {
    EXPECT_NEAR(mm[0][l], 10.0 + a[l], 1e-12);
    EXPECT_NEAR(mm[3][l], 10.0 + b[l], 1e-12);
    EXPECT_NEAR(mm[1][l], 10.0, 1e-12);
  }
}

TEST(Taguchi, AnovaRejectsBadInput) {
  EXPECT_THROW(anova(l16_array(), std::vector<double>(15, 1.0), {"a", "b", "c", "d", "e"}, {2}, 4),
               std::invalid_argument);
  EXPECT_THROW(anova(l16_array(), std::vector<double>(16, 1.0), {"a", "b"}, {2}, 4), std::invalid_argument);
}
