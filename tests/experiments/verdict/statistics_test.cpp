// The verdict's distributions and tests against closed forms and tables
// that do not share its code: Student's t with 1 and 2 degrees of freedom
// has an elementary CDF, the normal limit is erfc, the incomplete beta has
// closed forms for a or b = 1, and the quantiles are the textbook table's.
#include <gtest/gtest.h>
#include <cmath>
#include "experiments/verdict/statistics.h"

namespace lb {
namespace {

TEST(Statistics, IncompleteBetaClosedForms) {
  for (double x : {0.01, 0.2, 0.5, 0.77, 0.999}) {
    EXPECT_NEAR(regularizedIncompleteBeta(1, 1, x), x, 1e-13);
    EXPECT_NEAR(regularizedIncompleteBeta(3.5, 1, x), std::pow(x, 3.5), 1e-12);
    EXPECT_NEAR(regularizedIncompleteBeta(1, 2.5, x), 1 - std::pow(1 - x, 2.5), 1e-12);
    // I_x(1/2, 1/2) = (2/π) asin √x.
    EXPECT_NEAR(regularizedIncompleteBeta(0.5, 0.5, x), 2 / M_PI * std::asin(std::sqrt(x)), 1e-12);
  }
}

TEST(Statistics, StudentTCdfClosedForms) {
  for (double t : {-30.0, -2.5, -0.3, 0.0, 0.4, 1.7, 12.0}) {
    // ν = 1 is Cauchy's distribution, ν = 2 has F(t) = 1/2 + t / (2 √(2 + t²)).
    EXPECT_NEAR(studentTCdf(t, 1), 0.5 + std::atan(t) / M_PI, 1e-12) << t;
    EXPECT_NEAR(studentTCdf(t, 2), 0.5 + t / (2 * std::sqrt(2 + t * t)), 1e-12) << t;
    EXPECT_NEAR(studentTCdf(t, INFINITY), 0.5 * std::erfc(-t / std::sqrt(2.0)), 1e-15) << t;
    EXPECT_NEAR(studentTCdf(t, 1e7), 0.5 * std::erfc(-t / std::sqrt(2.0)), 1e-6) << t;
  }
}

TEST(Statistics, StudentTQuantilesMatchTheTable) {
  // Two-sided 95 % (the 0.975 quantile) and 99 % (0.995), any textbook's table.
  struct Row {
    double dof, q975, q995;
  };
  for (Row r : {Row{1, 12.7062, 63.6567}, Row{2, 4.3027, 9.9248}, Row{5, 2.5706, 4.0321}, Row{10, 2.2281, 3.1693},
                Row{30, 2.0423, 2.7500}, Row{INFINITY, 1.9600, 2.5758}}) {
    EXPECT_NEAR(studentTQuantile(0.975, r.dof), r.q975, 5e-5) << r.dof;
    EXPECT_NEAR(studentTQuantile(0.995, r.dof), r.q995, 5e-5) << r.dof;
    EXPECT_NEAR(studentTQuantile(0.025, r.dof), -r.q975, 5e-5) << r.dof;
  }
  for (double dof : {1.3, 4.0, 17.5})
    for (double p : {0.6, 0.9, 0.999}) EXPECT_NEAR(studentTCdf(studentTQuantile(p, dof), dof), p, 1e-12);
}

TEST(Statistics, SatterthwaiteDegrees) {
  // Two equal variances of n − 1 = 4 degrees of freedom each: 8.
  EXPECT_NEAR(satterthwaiteDof({1.0, 1.0}, {4, 4}), 8, 1e-12);
  // One dominant term: its own degrees of freedom.
  EXPECT_NEAR(satterthwaiteDof({1.0, 1e-9}, {3, 100}), 3, 1e-6);
  // A term known exactly adds variance but no uncertainty: (1 + 1)² / (1²/2) = 8.
  EXPECT_NEAR(satterthwaiteDof({1.0, 1.0}, {2, INFINITY}), 8, 1e-12);
  EXPECT_TRUE(std::isinf(satterthwaiteDof({1.0}, {INFINITY})));
}

TEST(Statistics, TwoSidedP) {
  EXPECT_NEAR(twoSidedP(1.96, 1, INFINITY), 0.05, 1e-4);
  EXPECT_NEAR(twoSidedP(-12.7062, 1, 1), 0.05, 1e-5);
  EXPECT_EQ(twoSidedP(0, 0, 3), 1);
  EXPECT_EQ(twoSidedP(1e-9, 0, 3), 0);
}

TEST(Statistics, HolmStepDown) {
  // Sorted 0.005, 0.01, 0.03, 0.04 are multiplied by 4, 3, 2, 1 (0.02, 0.03,
  // 0.06, 0.04) and made non-decreasing (0.02, 0.03, 0.06, 0.06).
  std::vector<double> adjusted = holmAdjust({0.01, 0.04, 0.03, 0.005});
  std::vector<double> expected = {0.03, 0.06, 0.06, 0.02};
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(adjusted[i], expected[i], 1e-15) << i;
  // At α = 0.05 Holm rejects the first two in order and stops at 0.03 > 0.05/2.
  EXPECT_LT(adjusted[3], 0.05);
  EXPECT_LT(adjusted[0], 0.05);
  EXPECT_GE(adjusted[2], 0.05);
  // 0.8 · 2 is capped at 1, and 0.9 may not fall below it: both 1.
  EXPECT_EQ(holmAdjust({0.9, 0.8}), (std::vector<double>{1, 1}));
}

TEST(Statistics, BatchMeansOfEqualBatchesIsTheSampleVarianceOverK) {
  std::vector<double> sums = {1, 2, 3, 6}, weights = {1, 1, 1, 1};
  BatchMeans b = batchMeans(sums, weights);
  EXPECT_NEAR(b.mean, 3, 1e-15);
  EXPECT_NEAR(b.varianceOfMean, (4 + 1 + 0 + 9) / 3.0 / 4, 1e-15);  // s² / k
  EXPECT_EQ(b.dof, 3);
  // Empty batches do not count.
  BatchMeans c = batchMeans({2, 0, 4}, {1, 0, 1});
  EXPECT_EQ(c.batches, 2);
  EXPECT_NEAR(c.mean, 3, 1e-15);
}

}  // namespace
}  // namespace lb
