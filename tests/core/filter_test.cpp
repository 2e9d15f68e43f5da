// Pixel filters (core/filter.h): the offsets a camera sample draws follow the
// density the filter states (χ²), and the weighted samples estimate the
// normalised filter written again from its definition
// (tests/support/filter_reference.h), cell by cell; evaluate(), which splats
// use, is that normalised filter.
#include <gtest/gtest.h>
#include "core/filter.h"
#include "core/rng.h"
#include "tests/support/filter_reference.h"
#include "tests/support/statistics.h"

namespace lb {
namespace {

using test::FilterCase;

TEST(PixelFilter, OffsetsFollowTheStatedDensity) {
  const auto cases = test::filterCases();
  const int cells = 16, sub = 48;
  const size_t n = 200000;
  for (const FilterCase& c : cases) {
    PixelFilter f = c.make();
    double r = c.radius, w = 2 * r / cells;
    std::vector<double> observed(size_t(cells * cells), 0), expected(size_t(cells * cells), 0);
    Pcg32 rng(0xf117e4, 7);
    for (size_t i = 0; i < n; ++i) {
      Vec2 o = f.sample(rng.next2D()).offset;
      ASSERT_LE(std::abs(o.x), r) << c.name;
      ASSERT_LE(std::abs(o.y), r) << c.name;
      int cx = std::min(cells - 1, int((o.x + r) / w)), cy = std::min(cells - 1, int((o.y + r) / w));
      observed[size_t(cy * cells + cx)] += 1;
    }
    // The stated pdf integrated over each cell (midpoints of a sub-grid).
    for (int cy = 0; cy < cells; ++cy)
      for (int cx = 0; cx < cells; ++cx) {
        double sum = 0;
        for (int j = 0; j < sub; ++j)
          for (int i = 0; i < sub; ++i)
            sum += f.pdf(Vec2(float(-r + (cx + (i + 0.5) / sub) * w), float(-r + (cy + (j + 0.5) / sub) * w)));
        expected[size_t(cy * cells + cx)] = sum * (w / sub) * (w / sub) * double(n);
      }
    auto result = test::chi2Test(observed, expected);
    EXPECT_TRUE(result.passed(test::sidak(0.01, int(cases.size())))) << c.name << ": " << result.message << " p = "
                                                                     << result.pValue;
  }
}

// E[w · 1{offset in cell}] = ∫_cell f̂: the weights make any density right,
// so this checks what the pixel estimates, not how it is sampled. Cells
// that a density ∝ |f| would hit fewer than 100 times (a Gaussian's corners)
// are pooled into one, so that every z-test has enough hits for its normal
// approximation.
TEST(PixelFilter, WeightedSamplesEstimateTheNormalisedFilter) {
  const auto cases = test::filterCases();
  const int cells = 6;
  const size_t n = 400000;
  const double alpha = test::sidak(0.01, int(cases.size()) * (cells * cells + 1));
  const double zMax = test::normalCritical(alpha);
  for (const FilterCase& c : cases) {
    PixelFilter f = c.make();
    double r = c.radius, w = 2 * r / cells, total = test::filterReferenceIntegral(c, -r, r);
    double absTotal = test::filterReferenceIntegral(c, -r, r, 2000, true);
    std::vector<int> pool(size_t(cells * cells));  // the cell's z-test: itself, or the pooled one (index cells²)
    std::vector<double> want(size_t(cells * cells) + 1, 0.0);
    for (int cy = 0; cy < cells; ++cy)
      for (int cx = 0; cx < cells; ++cx) {
        int k = cy * cells + cx;
        auto integral = [&](int i, bool absolute) {
          return test::filterReferenceIntegral(c, -r + i * w, -r + (i + 1) * w, 2000, absolute);
        };
        double hits = double(n) * integral(cx, true) * integral(cy, true) / (absTotal * absTotal);
        pool[size_t(k)] = hits < 100 ? cells * cells : k;
        want[size_t(pool[size_t(k)])] += integral(cx, false) * integral(cy, false) / (total * total);
      }
    std::vector<test::RunningStats> cell(size_t(cells * cells) + 1);
    test::RunningStats all;
    Pcg32 rng(0x3e16, 11);
    for (size_t i = 0; i < n; ++i) {
      PixelFilter::Sample s = f.sample(rng.next2D());
      int cx = std::min(cells - 1, int((s.offset.x + r) / w)), cy = std::min(cells - 1, int((s.offset.y + r) / w));
      int hit = pool[size_t(cy * cells + cx)];
      for (int k = 0; k <= cells * cells; ++k) cell[size_t(k)].add(k == hit ? s.weight : 0.0);
      all.add(s.weight);
    }
    for (int k = 0; k <= cells * cells; ++k) {
      const test::RunningStats& s = cell[size_t(k)];
      if (s.mean == 0 && want[size_t(k)] == 0) continue;  // an empty pool
      double z = test::zScore(s.mean, s.varianceOfMean(), want[size_t(k)], 0);
      EXPECT_LT(std::abs(z), zMax) << c.name << " cell " << k << " of " << cells << "²: " << s.mean << " vs " << want[size_t(k)];
    }
    EXPECT_LT(std::abs(test::zScore(all.mean, all.varianceOfMean(), 1, 0)), zMax) << c.name << ": E[w] = " << all.mean;
  }
}

// The splat weight f̂(offset) against the definition, at points across the
// support. Float evaluation of a dozen operations and a float integral: a
// relative error of 1e-5 of the filter's peak bounds both.
TEST(PixelFilter, EvaluateIsTheNormalisedFilter) {
  for (const FilterCase& c : test::filterCases()) {
    PixelFilter f = c.make();
    double total = test::filterReferenceIntegral(c, -c.radius, c.radius);
    double peak = test::filterReference1D(c, 0) * test::filterReference1D(c, 0) / (total * total);
    for (double x = -c.radius - 0.3; x <= c.radius + 0.3; x += 0.173)
      for (double y = -c.radius - 0.3; y <= c.radius + 0.3; y += 0.219) {
        double want = test::filterReference1D(c, x) * test::filterReference1D(c, y) / (total * total);
        EXPECT_NEAR(f.evaluate(Vec2(float(x), float(y))), want, 1e-5 * peak) << c.name << " at (" << x << ", " << y << ")";
      }
  }
}

TEST(PixelFilter, TheOnePixelBoxIsTheDefaultAndHasNoMargin) {
  PixelFilter f;
  EXPECT_TRUE(f.isPixelBox());
  EXPECT_EQ(f.margin(), 0.f);
  EXPECT_EQ(PixelFilter(PixelFilter::Type::Gaussian, 2, 0.5f).margin(), 1.5f);
  for (const std::string& name : PixelFilter::names()) EXPECT_EQ(PixelFilter::names()[size_t(PixelFilter::typeNamed(name))], name);
}

}  // namespace
}  // namespace lb
