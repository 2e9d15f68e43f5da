// The microfacet distributions (core/bsdfs/microfacet.h) against their
// definitions, by quadrature over the sphere, independent of the sampling
// code: D is normalised in projected area, ∫ D(m) cos θm dm = 1, and Smith's
// Λ is the one D implies, ∫ D(m) max(0, w·m) dm = cos θ (1 + Λ(w)) (Heitz
// 2014, Eqs. 4 and 16). A Λ or D off by a few per cent fails.
#include <gtest/gtest.h>
#include <cmath>
#include "core/bsdfs/microfacet.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

TEST(Microfacet, DistributionIsNormalisedAndLambdaMatchesIt) {
  for (MicrofacetKind kind : {MicrofacetKind::GGX, MicrofacetKind::Beckmann})
    for (float alpha : {0.15f, 0.4f, 0.8f}) {
      Microfacet mf(alpha, kind);
      const char* name = kind == MicrofacetKind::GGX ? "ggx" : "beckmann";
      SphereIntegral area = integrateSphere(
          [&](const Vec3& m) { return glm::dvec3(m.z > 0 ? double(mf.D(m)) * m.z : 0.0); }, 1e-5);
      EXPECT_NEAR(area.value.x, 1.0, 1e-3 + area.error.x) << name << " alpha " << alpha;
      for (float deg : {20.f, 60.f, 80.f}) {
        float t = glm::radians(deg);
        Vec3 w(std::sin(t), 0, std::cos(t));
        SphereIntegral seen = integrateSphere(
            [&](const Vec3& m) { return glm::dvec3(m.z > 0 ? double(mf.D(m)) * std::max(0.f, glm::dot(w, m)) : 0.0); },
            1e-5);
        double expected = w.z * (1 + double(mf.lambda(w)));
        EXPECT_NEAR(seen.value.x, expected, 2e-3 * expected + seen.error.x) << name << " alpha " << alpha << " at " << deg << "°";
      }
    }
}

// Beckmann's normals are drawn from D cos θm: the fraction with θm below a
// cone is 1 − exp(−tan²θ/α²) in closed form (Walter et al. 2007, Eq. 28).
TEST(Microfacet, BeckmannNormalsFollowTheirClosedFormCdf) {
  Microfacet mf(0.3f, MicrofacetKind::Beckmann);
  const int n = 200000;
  int below = 0;
  const double tanCut = 0.25, expected = 1 - std::exp(-tanCut * tanCut / (0.3 * 0.3));
  for (int i = 0; i < n; ++i) {
    Vec3 m = mf.sampleNormal(Vec3(0, 0, 1), Vec2((i + 0.5f) / n, 0.37f));
    below += std::sqrt(m.x * m.x + m.y * m.y) / m.z < tanCut;
  }
  EXPECT_NEAR(double(below) / n, expected, 1e-4);
}

}  // namespace
}  // namespace lb::test
