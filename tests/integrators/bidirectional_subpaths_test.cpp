// Camera subpaths that end early (integrators/bidirectional/subpaths.h,
// WalkStop): progressive photon mapping's camera walk ends at its first
// non-specular vertex. It must be exactly the full walk's prefix up to that
// vertex (same numbers, same vertices), so that ending early changes the
// rays traced and nothing else.
#include <gtest/gtest.h>
#include "core/sampler.h"
#include "integrators/bidirectional/subpaths.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

using bidir::Vertex;

bool specular(const Vertex& v) { return v.type == bidir::VertexType::Surface && v.si.material && v.si.material->isDelta(); }

TEST(BidirectionalSubpaths, AWalkEndingAtItsFirstNonSpecularVertexIsTheFullWalksPrefix) {
  // The Cornell box with a mirror and a glass sphere: camera rays reach the
  // walls directly and through one or more specular bounces.
  SceneFile sf = loadShippedScene("cornell-box-spheres", 32, 32);
  const Scene& scene = *sf.scene;
  PathLength length;
  length.maxDepth = 12;
  length.russianRoulette = true;  // roulette draws after the stop: both walks must still agree up to it
  std::vector<Vertex> full(13), stopped(13);
  IndependentSampler a(7), b(7);
  uint64_t rays = 0;
  int throughSpecular = 0, endedByStop = 0;
  for (uint64_t i = 0; i < 4000; ++i) {
    a.start(i, 0), b.start(i, 0);
    Vec2 raster(float(i % 32) + 0.5f, float((i / 32) % 32) + 0.5f);
    int nf = bidir::generateCameraSubpath(scene, a, length, raster, full, rays);
    int ns = bidir::generateCameraSubpath(scene, b, length, raster, stopped, rays, {},
                                          bidir::WalkStop::AtFirstNonSpecular);
    ASSERT_LE(ns, nf) << "path " << i;
    for (int k = 0; k < ns; ++k) {
      const Vertex &x = stopped[size_t(k)], &y = full[size_t(k)];
      ASSERT_EQ(x.p, y.p) << "path " << i << ", vertex " << k;
      ASSERT_EQ(x.beta, y.beta) << "path " << i << ", vertex " << k;
      ASSERT_EQ(x.pdfFwd, y.pdfFwd) << "path " << i << ", vertex " << k;
      ASSERT_EQ(x.type, y.type) << "path " << i << ", vertex " << k;
      // The last vertex's lobe is never sampled in the shortened walk.
      if (k + 1 < ns) {
        ASSERT_EQ(x.delta, y.delta) << "path " << i << ", vertex " << k;
      }
    }
    // Every vertex between the camera and the last is specular (its material
    // is, from the scene's definition); the last is one photons are merged
    // at (as VCM's ppm mode asks), unless the full walk ended there too.
    for (int k = 1; k + 1 < ns; ++k) ASSERT_TRUE(specular(stopped[size_t(k)])) << "path " << i << ", vertex " << k;
    if (ns < nf) {
      ASSERT_FALSE(specular(stopped[size_t(ns - 1)])) << "path " << i;
      ASSERT_TRUE(stopped[size_t(ns - 1)].mergeable()) << "path " << i;
      ++endedByStop;
    }
    throughSpecular += ns > 2;
  }
  // The case that matters was exercised: paths stopped behind a mirror or glass.
  EXPECT_GT(throughSpecular, 100);
  EXPECT_GT(endedByStop, 1000);
}

}  // namespace
}  // namespace lb::test
