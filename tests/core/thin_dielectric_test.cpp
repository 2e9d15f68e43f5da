// Thin dielectric slab (Mitsuba `thindielectric`): lobe probabilities against
// the Fresnel equations written out here, energy, directions, the index-matched
// limit, a known value, and the YAML factory.
#include <gtest/gtest.h>
#include <cmath>
#include "core/bsdfs/material_factory.h"
#include "core/bsdfs/thin_dielectric.h"
#include "core/error.h"
#include "core/rng.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

// Single-interface Fresnel reflectance from Snell's law, independent of fresnel.h.
double fresnel(double cosI, double eta) {
  double sinT = std::sqrt(1 - cosI * cosI) / eta;
  if (sinT >= 1) return 1;  // total internal reflection
  double cosT = std::sqrt(1 - sinT * sinT);
  double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return (rs * rs + rp * rp) / 2;
}

// Slab reflectance R' = R + T²R / (1 - R²), T = 1 - R.
double slabReflectance(double cosI, double eta) {
  double R = fresnel(cosI, eta), T = 1 - R;
  return R < 1 ? R + T * T * R / (1 - R * R) : 1;
}

Vec3 direction(float cosTheta, bool below) {
  float s = std::sqrt(1 - cosTheta * cosTheta);
  return Vec3(0.8f * s, 0.6f * s, below ? -cosTheta : cosTheta);
}

const float Iors[] = {1.5f, 1.33f, 2.4f};
const float Cosines[] = {1.f, 0.7f, 0.3f, 0.05f};

TEST(ThinDielectric, ReflectionProbabilityMatchesSlabFresnel) {
  // 1/1.5 at cos 0.3 is beyond the critical angle: R = R' = 1.
  const float iors[] = {1.5f, 1.33f, 2.4f, 1 / 1.5f};
  int tests = 4 * 4 * 2;
  const int n = 100000;
  double z = normalCritical(0.01 / tests);
  uint64_t seed = 1;
  for (float ior : iors)
    for (float c : Cosines)
      for (bool below : {false, true}) {
        ThinDielectric slab(ior);
        Vec3 wo = direction(c, below);
        double Rp = slabReflectance(c, ior);
        Pcg32 rng(seed++, 7);
        int reflected = 0;
        for (int i = 0; i < n; ++i) {
          auto s = slab.sample(wo, rng.next1D(), rng.next2D(), TransportMode::Radiance);
          ASSERT_TRUE(s);
          if (s->lobe & BSDFReflection) ++reflected;
        }
        double sigma = std::sqrt(n * Rp * (1 - Rp));
        EXPECT_LE(std::abs(reflected - n * Rp), z * sigma + 1e-9)
            << "ior=" << ior << " cos=" << c << (below ? " below" : " above") << " R'=" << Rp;
      }
}

TEST(ThinDielectric, LobeProbabilitiesSumToOneAndWeightsAreOne) {
  for (float ior : Iors)
    for (float c : Cosines)
      for (bool below : {false, true}) {
        ThinDielectric slab(ior);
        Vec3 wo = direction(c, below);
        double Rp = slabReflectance(c, ior);
        auto r = slab.sample(wo, float(Rp / 2), Vec2(0.5f), TransportMode::Radiance);
        auto t = slab.sample(wo, float((1 + Rp) / 2), Vec2(0.5f), TransportMode::Radiance);
        ASSERT_TRUE(r && t);
        ASSERT_TRUE((r->lobe & BSDFReflection) && (t->lobe & BSDFTransmission));
        EXPECT_NEAR(r->pdf, Rp, 1e-5) << "ior=" << ior << " cos=" << c;
        EXPECT_NEAR(r->pdf + t->pdf, 1.f, 1e-6f);
        EXPECT_NEAR(r->weight().r, 1.f, 1e-5f);
        EXPECT_NEAR(t->weight().r, 1.f, 1e-5f);
        EXPECT_EQ(r->pdfRev, r->pdf);
        EXPECT_EQ(t->pdfRev, t->pdf);
      }
}

TEST(ThinDielectric, DirectionsAndTransportModes) {
  ThinDielectric slab(1.5f);
  for (bool below : {false, true}) {
    Vec3 wo = direction(0.6f, below);
    for (float uLobe : {0.01f, 0.99f}) {
      auto a = slab.sample(wo, uLobe, Vec2(0.3f), TransportMode::Radiance);
      auto b = slab.sample(wo, uLobe, Vec2(0.3f), TransportMode::Importance);
      ASSERT_TRUE(a && b);
      EXPECT_EQ(a->lobe, b->lobe);
      EXPECT_TRUE(a->isDelta());
      if (a->lobe & BSDFReflection) EXPECT_EQ(a->wi, Vec3(-wo.x, -wo.y, wo.z));
      else EXPECT_EQ(a->wi, -wo);  // straight through, no bending
      EXPECT_EQ(a->eta, 1.f);
      EXPECT_EQ(a->wi, b->wi);
      EXPECT_EQ(a->f, b->f);  // no 1/η² in either mode
      EXPECT_EQ(a->pdf, b->pdf);
    }
  }
  EXPECT_EQ(slab.flags(), uint32_t(BSDFReflection | BSDFTransmission | BSDFSpecular));
  EXPECT_EQ(slab.relativeEta(Vec3(0, 0, 1)), 1.f);
  EXPECT_EQ(slab.eval(Vec3(0, 0, 1), Vec3(0, 0, -1), TransportMode::Radiance).f, Color(0.f));
}

TEST(ThinDielectric, IndexMatchedSlabTransmitsEverything) {
  ThinDielectric slab(1.f);
  Pcg32 rng(3, 1);
  for (float c : Cosines)
    for (int i = 0; i < 1000; ++i) {
      Vec3 wo = direction(c, i % 2);
      auto s = slab.sample(wo, rng.next1D(), rng.next2D(), TransportMode::Radiance);
      ASSERT_TRUE(s);
      ASSERT_TRUE(s->lobe & BSDFTransmission);
      ASSERT_EQ(s->pdf, 1.f);
      ASSERT_NEAR(s->weight().r, 1.f, 1e-6f);
    }
}

TEST(ThinDielectric, NormalIncidenceKnownValue) {
  // R = ((1.5 - 1) / (1.5 + 1))² = 0.04; R' = 0.04 + 0.96² · 0.04 / (1 - 0.04²).
  double R = 0.04, Rp = R + 0.96 * 0.96 * R / (1 - R * R);
  EXPECT_NEAR(Rp, 0.0769, 1e-4);
  ThinDielectric slab(1.5f);
  auto s = slab.sample(Vec3(0, 0, 1), 0.f, Vec2(0.5f), TransportMode::Radiance);
  ASSERT_TRUE(s && (s->lobe & BSDFReflection));
  EXPECT_NEAR(s->pdf, Rp, 1e-6);
  EXPECT_NEAR(s->f.r, Rp, 1e-6);  // |cos θ| = 1
}

TEST(ThinDielectric, Factory) {
  Params p(YAML::Load("{type: thin_dielectric, ior: 1.33}"), "<test>", "materials[0]");
  auto m = makeMaterial(p);
  ASSERT_TRUE(dynamic_cast<ThinDielectric*>(m.get()));
  auto s = m->sample(Vec3(0, 0, 1), 0.f, Vec2(0.5f), TransportMode::Radiance);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->pdf, slabReflectance(1, 1.33), 1e-6);
  Params rough(YAML::Load("{type: thin_dielectric, roughness: 0.1}"), "<test>", "materials[0]");
  EXPECT_THROW(makeMaterial(rough), ConfigError);
  Params negative(YAML::Load("{type: thin_dielectric, ior: -1}"), "<test>", "materials[0]");
  EXPECT_THROW(makeMaterial(negative), ConfigError);
}

}  // namespace
}  // namespace lb::test
