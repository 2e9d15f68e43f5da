// The guided integrator's vertex recorder (integrators/guided/vertex_recorder.h)
// when a path branches (rrs: adrrs | ears splits continuations): each record
// is credited with the light of its own subtree only, written out by hand
// below from the order in which the path estimator reports a split
// (PathObserver, path_estimator.h), not computed by the recorder's rule.
#include "integrators/guided/vertex_recorder.h"

#include <gtest/gtest.h>

namespace lb::test {
namespace {

class NoMethod final : public guiding::GuidingMethod {
 public:
  std::unique_ptr<DirectionGuide> makeGuide(float) const override { return nullptr; }
  void learn(const guiding::TileRecords&) override {}
  std::vector<std::string> statistics() const override { return {}; }
  Image densityImage(const Vec3&, int, int) const override { return Image(1, 1); }
};

SurfaceInteraction surface() {
  SurfaceInteraction si;
  si.p = Vec3(0.f);
  si.ng = Vec3(0, 0, 1);
  si.wo = Vec3(0, 0, 1);
  return si;
}

PathState scattering(int nesting, int vertex, float beta, bool delta = false) {
  PathState s;
  s.nesting = nesting;
  s.vertex = vertex;
  s.beta = Color(beta);
  s.prevDelta = delta;
  s.ray.d = Vec3(0, 0, 1);
  return s;
}

// A path that splits at its second vertex (v1) into three continuations,
// the first of which splits none but scatters twice: events in the
// estimator's order, branches traced at once first, then the continuation
// the line goes on with (continuation 0, at the line's own nesting).
TEST(GuidedVertexRecorder, CreditsEachRecordWithItsOwnSubtreeOnly) {
  NoMethod method;
  std::vector<guiding::GuideVertex> records;
  guiding::VertexRecorder rec(records, method);
  const SurfaceInteraction si = surface();
  const BSDF* none = nullptr;
  auto grey = [](float v) { return Color(v); };
  const float third = 1.f / 3.f;

  rec.shaded(si, none, grey(0), grey(1));       // camera hit: nothing recorded yet
  rec.scattered(si, scattering(0, 0, 1));       // R0
  rec.shaded(si, none, grey(0), grey(2));       // v1, before its split
  rec.scattered(si, scattering(1, 1, third));   // R1: branch 1 at v1
  rec.shaded(si, none, grey(0.3f), grey(0.3f)); // its hit: emission 0.3
  rec.scattered(si, scattering(1, 2, third));   // R2: branch 1 at v2
  rec.shaded(si, none, grey(0), grey(0.6f));    // branch 1 ends
  rec.scattered(si, scattering(1, 1, third));   // R3: branch 2 at v1
  rec.shaded(si, none, grey(0.9f), grey(0.9f)); // branch 2 ends
  rec.scattered(si, scattering(0, 1, third));   // R4: continuation 0 at v1
  rec.shaded(si, none, grey(0.15f), grey(0.3f));
  rec.scattered(si, scattering(0, 2, third, true));  // a specular vertex: no record
  rec.shaded(si, none, grey(0.5f), grey(0.5f));      // its emission closes no record

  ASSERT_EQ(records.size(), 5u);
  // Incident light: each later contribution over the record's throughput.
  const float expected[5] = {
      2 + 0.3f + 0.6f + 0.9f + 0.3f + 0.5f,  // R0 (β = 1): everything after it
      (0.3f + 0.6f) / third,                 // R1: branch 1 only
      0.6f / third,                          // R2
      0.9f / third,                          // R3: branch 2 only
      (0.3f + 0.5f) / third,                 // R4: continuation 0 only
  };
  for (int r = 0; r < 5; ++r) EXPECT_NEAR(records[size_t(r)].incident.g, expected[r], 1e-5f) << "record " << r;
  // Emission each direction reached, over the record's throughput.
  const float emitted[5] = {0, 0.3f / third, 0, 0.9f / third, 0.15f / third};
  for (int r = 0; r < 5; ++r) EXPECT_NEAR(records[size_t(r)].emitted, emitted[r], 1e-5f) << "record " << r;
}

// rrs_split_light: a split's further continuations take light samples at
// the split's vertex before any of them is traced. That light is part of
// what the direction into the vertex brought back, so it goes to the
// vertex's ancestors, not to the branches' records. Seen failing (R0 short
// by the 0.5) with the recorder ignoring splitLight().
TEST(GuidedVertexRecorder, ASplitsLightSamplesCreditTheVertexsAncestors) {
  NoMethod method;
  std::vector<guiding::GuideVertex> records;
  guiding::VertexRecorder rec(records, method);
  const SurfaceInteraction si = surface();
  rec.shaded(si, nullptr, Color(0.f), Color(1.f));  // camera hit
  rec.scattered(si, scattering(0, 0, 1));            // R0
  rec.shaded(si, nullptr, Color(0.f), Color(2.f));  // v1: continuation 0's light samples
  rec.splitLight(Color(0.5f));                       // continuation 1's, at v1
  rec.scattered(si, scattering(1, 1, 0.5f));         // R1: continuation 1 at v1
  rec.shaded(si, nullptr, Color(0.3f), Color(0.3f));
  rec.scattered(si, scattering(0, 1, 0.5f));         // R2: continuation 0 at v1
  rec.shaded(si, nullptr, Color(0.f), Color(0.4f));
  ASSERT_EQ(records.size(), 3u);
  EXPECT_NEAR(records[0].incident.g, 2 + 0.5f + 0.3f + 0.4f, 1e-5f);
  EXPECT_NEAR(records[1].incident.g, 0.3f / 0.5f, 1e-5f);
  EXPECT_NEAR(records[2].incident.g, 0.4f / 0.5f, 1e-5f);
}

// Without branches the chain is the whole path: every record gets every later term.
TEST(GuidedVertexRecorder, AnUnbranchedPathCreditsEveryEarlierRecord) {
  NoMethod method;
  std::vector<guiding::GuideVertex> records;
  guiding::VertexRecorder rec(records, method);
  const SurfaceInteraction si = surface();
  for (int v = 0; v < 4; ++v) {
    rec.scattered(si, scattering(0, v, 0.5f));
    rec.shaded(si, nullptr, Color(0.f), Color(1.f));
  }
  ASSERT_EQ(records.size(), 4u);
  for (size_t r = 0; r < 4; ++r) EXPECT_NEAR(records[r].incident.r, float(4 - r) / 0.5f, 1e-5f) << r;
}

}  // namespace
}  // namespace lb::test
