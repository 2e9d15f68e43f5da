#include "tests/support/statistics.h"
#include <algorithm>
#include <cmath>
#include <sstream>
#include "core/frame.h"
#include "core/rng.h"

namespace lb::test {

double gammaQ(double a, double x) {
  if (x <= 0) return 1;
  double gln = std::lgamma(a);
  if (x < a + 1) {  // series for P, Q = 1 - P
    double ap = a, sum = 1 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-15) break;
    }
    return 1 - sum * std::exp(-x + a * std::log(x) - gln);
  }
  // Continued fraction for Q (modified Lentz).
  double b = x + 1 - a, c = 1 / 1e-300, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

namespace {
// Regularised incomplete beta I_x(a, b) by its continued fraction (modified
// Lentz; Numerical Recipes §6.4).
double incompleteBeta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  if (x > (a + 1) / (a + b + 2)) return 1 - incompleteBeta(b, a, 1 - x);
  double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x)) / a;
  const double tiny = 1e-300;
  double f = 1, c = 1, d = 0;
  for (int i = 0; i <= 400; ++i) {
    int m = i / 2;
    double numerator = i == 0 ? 1
                       : i % 2 == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                    : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
    d = 1 + numerator * d;
    d = std::abs(d) < tiny ? tiny : d;
    d = 1 / d;
    c = 1 + numerator / c;
    c = std::abs(c) < tiny ? tiny : c;
    f *= c * d;
    if (std::abs(1 - c * d) < 1e-14) break;
  }
  return front * (f - 1);
}
}  // namespace

double studentCritical(double alpha, double dof) {
  // P(|T| > t) = I_{ν/(ν+t²)}(ν/2, 1/2); bisection on t.
  auto tail = [&](double t) { return incompleteBeta(dof / 2, 0.5, dof / (dof + t * t)); };
  double lo = 0, hi = 1;
  while (tail(hi) > alpha) hi *= 2;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    (tail(mid) > alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double normalCritical(double alpha) {
  double lo = 0, hi = 40;  // erfc(z/√2) = alpha
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    if (std::erfc(mid / std::sqrt(2.0)) > alpha) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Pooling as in Nori's chi2test: cells sorted by expected count; the low ones
// are pooled, and the pool keeps absorbing the next cells in that order until
// its expected count reaches minExpected. So a pool that is still too small
// after the last low cell is merged into the neighbour with the smallest
// expected count that passed, never dropped: samples piling up where the pdf
// says almost nothing should go still count against the sampler.
Chi2Result chi2Test(const std::vector<double>& observed, const std::vector<double>& expected, double minExpected) {
  Chi2Result r;
  std::vector<size_t> order(observed.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double pooledObs = 0, pooledExp = 0;
  int cells = 0;
  for (size_t i : order) {
    if (expected[i] <= 0) {
      if (observed[i] > 0) {
        std::ostringstream s;
        s << "cell " << i << " has " << observed[i] << " samples but zero expected count";
        r.message = s.str();
        return r;
      }
      continue;  // nothing expected, nothing seen: not a cell of the test
    }
    if (expected[i] < minExpected || (pooledExp > 0 && pooledExp < minExpected)) {
      pooledObs += observed[i], pooledExp += expected[i];
      continue;
    }
    r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pooledExp > 0) {
    r.statistic += (pooledObs - pooledExp) * (pooledObs - pooledExp) / pooledExp;
    ++cells;
  }
  r.dof = cells - 1;
  if (r.dof <= 0) {
    r.message = "too few cells with enough expected samples";
    return r;
  }
  r.pValue = gammaQ(r.dof / 2.0, r.statistic / 2.0);
  return r;
}

namespace {
// ∫∫ f over [z0,z1]×[p0,p1] by an adaptive midpoint rule: refine where the 4×4
// and 8×8 rules disagree (pdf discontinuities at a light's silhouette or a cone
// edge). Midpoints never touch cell edges, so a discontinuity lying exactly on
// an edge (a hemisphere's rim) is not smeared into the neighbouring cell.
template <typename F>
double midpoint(const F& f, double z0, double z1, double p0, double p1, int n) {
  double hz = (z1 - z0) / n, hp = (p1 - p0) / n, sum = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) sum += f(z0 + (a + 0.5) * hz, p0 + (b + 0.5) * hp);
  return sum * hz * hp;
}
template <typename F>
double adaptive(const F& f, double z0, double z1, double p0, double p1, int depth, int minDepth = 1) {
  if (minDepth <= 0) {
    double coarse = midpoint(f, z0, z1, p0, p1, 4), fine = midpoint(f, z0, z1, p0, p1, 8);
    if (depth == 0 || std::abs(fine - coarse) <= 1e-4 * std::abs(fine) + 1e-12 * (z1 - z0) * (p1 - p0)) return fine;
  }
  double zm = 0.5 * (z0 + z1), pm = 0.5 * (p0 + p1);
  return adaptive(f, z0, zm, p0, pm, depth - 1, minDepth - 1) + adaptive(f, zm, z1, p0, pm, depth - 1, minDepth - 1) +
         adaptive(f, z0, zm, pm, p1, depth - 1, minDepth - 1) + adaptive(f, zm, z1, pm, p1, depth - 1, minDepth - 1);
}
// n×n Gauss–Legendre product rule (n = 4 or 8) over [z0,z1]×[p0,p1]: exact
// for polynomials of degree 2n−1 in each variable, so smooth lobes converge
// in a few refinements where a midpoint rule would need thousands of cells.
template <typename F>
glm::dvec3 gauss3(const F& f, double z0, double z1, double p0, double p1, int n) {
  static const double x4[] = {0.3399810435848563, 0.8611363115940526}, w4[] = {0.6521451548625461, 0.3478548451374538};
  static const double x8[] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363},
                      w8[] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  const double *x = n == 4 ? x4 : x8, *w = n == 4 ? w4 : w8;
  double cz = 0.5 * (z0 + z1), hz = 0.5 * (z1 - z0), cp = 0.5 * (p0 + p1), hp = 0.5 * (p1 - p0);
  glm::dvec3 sum(0.0);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      double za = cz + (a % 2 ? 1 : -1) * hz * x[a / 2], pb = cp + (b % 2 ? 1 : -1) * hp * x[b / 2];
      sum += w[a / 2] * w[b / 2] * f(za, pb);
    }
  return sum * hz * hp;
}
template <typename F>
void adaptiveAbs(const F& f, double z0, double z1, double p0, double p1, double tolerance, int depth,
                 SphereIntegral& out) {
  glm::dvec3 coarse = gauss3(f, z0, z1, p0, p1, 4), fine = gauss3(f, z0, z1, p0, p1, 8);
  glm::dvec3 diff = glm::abs(fine - coarse);
  if (depth == 0 || std::max(diff.x, std::max(diff.y, diff.z)) <= tolerance) {
    out.value += fine, out.error += diff;
    return;
  }
  double zm = 0.5 * (z0 + z1), pm = 0.5 * (p0 + p1);
  for (auto [a0, a1] : {std::pair{z0, zm}, std::pair{zm, z1}})
    for (auto [b0, b1] : {std::pair{p0, pm}, std::pair{pm, p1}}) adaptiveAbs(f, a0, a1, b0, b1, tolerance / 4, depth - 1, out);
}
}  // namespace

SphereIntegral integrateSphere(const std::function<glm::dvec3(const Vec3&)>& fn, double absTolerance, int thetaCells,
                               int phiCells, const Frame& frame, int maxDepth) {
  auto f = [&](double theta, double phi) {
    double z = std::cos(theta), r = std::sin(theta);
    glm::dvec3 local(r * std::cos(phi), r * std::sin(phi), z);
    glm::dvec3 world = glm::dvec3(frame.s) * local.x + glm::dvec3(frame.t) * local.y + glm::dvec3(frame.n) * local.z;
    return r * fn(Vec3(world));
  };
  SphereIntegral out;
  double cellTolerance = absTolerance / (thetaCells * phiCells);
  for (int ti = 0; ti < thetaCells; ++ti)
    for (int pi = 0; pi < phiCells; ++pi)
      adaptiveAbs(f, M_PI * ti / thetaCells, M_PI * (ti + 1) / thetaCells, 2 * M_PI * pi / phiCells,
                  2 * M_PI * (pi + 1) / phiCells, cellTolerance, maxDepth, out);
  return out;
}

// Cells are uniform in θ ∈ [0, θmax] and φ; θ is computed in double from the
// direction's components so that narrow caps (distant lights) keep their
// resolution (z = cosθ would be quantised by float rounding near 1).
double SphereHistogramTest::thetaMax() const { return std::acos(std::max(-1.0, zMin)); }

int SphereHistogramTest::cellOf(const Vec3& world) const {
  int cells = thetaCells * phiCells;
  Vec3 w = frame.toLocal(world);
  glm::dvec3 d(w);
  double theta = std::atan2(std::sqrt(d.x * d.x + d.y * d.y), d.z);
  if (theta > thetaMax()) return cells + 1;
  int ti = std::min(thetaCells - 1, int(theta / thetaMax() * thetaCells));
  double phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * M_PI;
  int pi = std::min(phiCells - 1, int(phi / (2 * M_PI) * phiCells));
  return ti * phiCells + pi;
}

// ∫ pdf dω over one cell, integrated in (θ, φ) with dω = sinθ dθ dφ: a lobe
// that is a narrow spike at a pole is resolved in θ, not squeezed into z.
double SphereHistogramTest::cellIntegral(const PdfFn& pdf, int cell, int depth, int minDepth) const {
  auto f = [&](double theta, double phi) {
    double z = std::cos(theta), r = std::sin(theta);
    glm::dvec3 local(r * std::cos(phi), r * std::sin(phi), z);
    glm::dvec3 world = glm::dvec3(frame.s) * local.x + glm::dvec3(frame.t) * local.y + glm::dvec3(frame.n) * local.z;
    return r * pdf(Vec3(world));
  };
  int cells = thetaCells * phiCells;
  if (cell == cells + 1) return zMin > -1 ? adaptive(f, thetaMax(), M_PI, 0, 2 * M_PI, depth + 2, 3) : 0;
  int ti = cell / phiCells, pi = cell % phiCells;
  double t0 = thetaMax() * ti / thetaCells, t1 = thetaMax() * (ti + 1) / thetaCells;
  double p0 = 2 * M_PI * pi / phiCells, p1 = 2 * M_PI * (pi + 1) / phiCells;
  return adaptive(f, t0, t1, p0, p1, depth, minDepth);
}

std::vector<double> SphereHistogramTest::expectedCounts(const PdfFn& pdf) const {
  int cells = thetaCells * phiCells;
  std::vector<double> expected(size_t(cells) + 2, 0);
  double total = 0;
  for (int c = 0; c <= cells + 1; ++c) {
    if (c == cells) continue;
    double integral = cellIntegral(pdf, c, 5);
    expected[size_t(c)] = integral * double(samples);
    total += integral;
  }
  expected[size_t(cells)] = std::max(0.0, 1 - total) * double(samples);  // failed samples
  return expected;
}

std::vector<double> SphereHistogramTest::observedCounts(const SampleFn& sample, uint64_t seed) const {
  int cells = thetaCells * phiCells;
  std::vector<double> observed(size_t(cells) + 2, 0);
  Pcg32 rng(seed, 7);
  for (size_t i = 0; i < samples; ++i) {
    Vec2 u = rng.next2D();
    float uLobe = rng.next1D();
    auto w = sample(u, uLobe);
    observed[size_t(w ? cellOf(glm::normalize(*w)) : cells)] += 1;
  }
  return observed;
}

Chi2Result SphereHistogramTest::compare(const std::vector<double>& observed, std::vector<double> expected,
                                        const PdfFn& pdf) const {
  int cells = thetaCells * phiCells;
  for (int c = 0; c < cells; ++c)
    if (observed[size_t(c)] > 0 && expected[size_t(c)] == 0)
      expected[size_t(c)] = cellIntegral(pdf, c, 8, 6) * double(samples);  // forced 512² sub-grid
  return chi2Test(observed, expected);
}

Chi2Result SphereHistogramTest::run(const SampleFn& sample, const PdfFn& pdf, uint64_t seed) const {
  return compare(observedCounts(sample, seed), expectedCounts(pdf), pdf);
}

Chi2Result DiskHistogramTest::run(const SampleFn& sample, const PdfFn& pdf, uint64_t seed) const {
  int cells = radialCells * phiCells;
  std::vector<double> observed(size_t(cells) + 1, 0), expected(size_t(cells) + 1, 0);
  Pcg32 rng(seed, 11);
  for (size_t i = 0; i < samples; ++i) {
    auto p = sample(rng.next2D());
    glm::dvec2 d = p ? glm::dvec2(*p) : glm::dvec2(2.0);
    double r2 = glm::dot(d, d);
    if (!(r2 < 1)) {
      observed[size_t(cells)] += 1;
      continue;
    }
    double phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += 2 * M_PI;
    int ri = std::min(radialCells - 1, int(r2 * radialCells)), pi = std::min(phiCells - 1, int(phi / (2 * M_PI) * phiCells));
    observed[size_t(ri * phiCells + pi)] += 1;
  }
  // dA = ½ d(r²) dφ; a 16×16 midpoint rule per cell (exact for constant pdfs).
  double total = 0;
  for (int ri = 0; ri < radialCells; ++ri)
    for (int pi = 0; pi < phiCells; ++pi) {
      double s0 = double(ri) / radialCells, hs = 1.0 / radialCells / 16;
      double p0 = 2 * M_PI * pi / phiCells, hp = 2 * M_PI / phiCells / 16, mass = 0;
      for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b) {
          double r = std::sqrt(s0 + (a + 0.5) * hs), phi = p0 + (b + 0.5) * hp;
          mass += pdf(Vec2(float(r * std::cos(phi)), float(r * std::sin(phi)))) * 0.5 * hs * hp;
        }
      expected[size_t(ri * phiCells + pi)] = mass * double(samples);
      total += mass;
    }
  expected[size_t(cells)] = std::max(0.0, 1 - total) * double(samples);
  return chi2Test(observed, expected);
}

}  // namespace lb::test
