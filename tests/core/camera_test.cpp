// Camera: both directions agree, generateRay's directions follow pdfWe (χ²),
// and the importance is normalised.
#include <gtest/gtest.h>
#include "core/camera.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

Camera testCamera() { return Camera(Vec3(1, 2, 3), Vec3(0, 0.5f, 0), Vec3(0, 1, 0), 50, 64, 48); }

TEST(Camera, RasterRoundTrip) {
  Camera cam = testCamera();
  Pcg32 rng(1, 1);
  for (int i = 0; i < 1000; ++i) {
    Vec2 raster(rng.next1D() * 64, rng.next1D() * 48);
    Ray r = cam.generateRay(raster);
    auto back = cam.rasterOf(r.d);
    ASSERT_TRUE(back);
    ASSERT_NEAR(back->x, raster.x, 1e-3f);
    ASSERT_NEAR(back->y, raster.y, 1e-3f);
  }
}

TEST(Camera, ImportanceIntegratesToOneOverTheImage) {
  // ∫ We(ω) cosθ dω over the sphere = 1 (We normalised over the whole image).
  Camera cam = testCamera();
  Pcg32 rng(2, 2);
  RunningStats est;
  for (int i = 0; i < 400000; ++i) {
    Vec3 w = sampleUniformSphere(rng.next2D());
    est.add(double(cam.importance(w)) * std::max(0.f, glm::dot(w, cam.forward())) / uniformSpherePdf());
  }
  EXPECT_LE(std::abs(est.mean - 1), normalCritical(0.01) * std::sqrt(est.varianceOfMean()));
}

// generateRay at raster positions uniform over the image must give directions
// distributed with pdfWe's direction density 1/(A cos³θ) (zero off the image):
// χ² on a cap around the view direction just wider than the image's corners.
TEST(Camera, DirectionPdfMatchesRayGeneration) {
  Camera cam = testCamera();
  Vec2 size(float(cam.width()), float(cam.height()));
  SphereHistogramTest t;
  t.frame = Frame(cam.forward());
  t.zMin = std::cos(1.1 * std::acos(double(glm::dot(cam.generateRay(Vec2(0.f)).d, cam.forward()))));
  auto r = t.run([&](Vec2 u, float) { return std::optional<Vec3>(cam.generateRay(u * size).d); },
                 [&](const Vec3& w) {
                   float pdfPos, pdfDir;
                   cam.pdfWe(w, &pdfPos, &pdfDir);
                   return double(pdfDir);
                 },
                 3);
  EXPECT_TRUE(r.passed(0.01)) << r.message << " p=" << r.pValue << " chi2=" << r.statistic << " dof=" << r.dof;
}

TEST(Camera, ConnectGivesRasterAndPdf) {
  Camera cam = testCamera();
  Ray r = cam.generateRay(Vec2(10.5f, 20.25f));
  Vec3 p = r.o + 3.f * r.d;
  auto c = cam.connect(p);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->raster.x, 10.5f, 1e-3f);
  EXPECT_NEAR(c->raster.y, 20.25f, 1e-3f);
  EXPECT_NEAR(c->dist, 3.f, 1e-5f);
  float cos = glm::dot(r.d, cam.forward());
  EXPECT_NEAR(c->We / c->pdf, 1 / (cam.imagePlaneArea() * cos * cos * cos * 9.f), 1e-6f);
  EXPECT_FALSE(cam.connect(cam.position() - cam.forward()));  // behind the camera
}

}  // namespace
}  // namespace lb::test
