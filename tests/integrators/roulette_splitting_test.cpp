// Learned Russian roulette and splitting (integrators/path_estimator/
// roulette_splitting.h, path_splitting.cpp):
//  * ADRRS's window and EARS's factor against the papers' rules, written out
//    case by case here;
//  * the cache's statistics against the definitions (mean, second moment,
//    variance, cost), exact whatever the order and the thread that recorded
//    them, with a sparse bin falling back to its cell;
//  * the pixel estimates: a 3 × 3 box of the passes' means, and EARS's
//    image factor sqrt(C / E) with E's largest errors left out;
//  * the estimator is unbiased under a deliberately wrong cache the test
//    controls (splitting 20-fold in some cells, roulette at 0.05 in others):
//    the furnace's analytic L = 2 and the Cornell box against classic roulette;
//  * the image does not depend on the thread count; refusals.
// (The learned caches of real renders are checked against classic roulette
// on three scenes in path_variants_test.cpp.)
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <cmath>
#include <cstring>
#include <random>
#include "integrators/integrator.h"
#include "core/frame.h"
#include "core/sampling.h"
#include "integrators/path_estimator/direction_guide.h"
#include "integrators/path_estimator/path_estimator.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

float meanOf(const Color& c) { return (c.r + c.g + c.b) / 3; }

TEST(RouletteSplitting, AdrrsKeepsTheContributionInsideItsWindow) {
  // s = 5: the window around the pixel estimate is [2/(1+s), 2s/(1+s)] = [1/3, 5/3].
  const float low = 2.f / 6.f, high = 10.f / 6.f;
  const Color mean(0.2f, 0.4f, 0.6f);  // avg_c(w · mean) = 0.4 w for a grey w
  for (float w : {0.01f, 0.5f, 0.8f, 1.f, 4.f, 4.2f, 40.f, 1000.f}) {
    float x = 0.4f * w;
    float expected = x < low ? x / low : x > high ? x / high : 1.f;
    EXPECT_NEAR(adrrsFactor(Color(w), mean), expected, 1e-5f * expected) << w;
  }
  // Per channel: w = (30, 0, 0) sees only the red mean.
  EXPECT_NEAR(adrrsFactor(Color(30, 0, 0), mean), (30 * 0.2f / 3) / high, 1e-5f);
  // Continuations that bring nothing back: x = 0, below the window (the clamp makes it 0.05).
  EXPECT_EQ(adrrsFactor(Color(5.f), Color(0.f)), 0.f);
  EXPECT_EQ(clampSplitFactor(1e6f), 20.f);
  EXPECT_EQ(clampSplitFactor(1e-6f), 0.05f);
  EXPECT_EQ(clampSplitFactor(0.f), 0.05f);
}

TEST(RouletteSplitting, EarsTakesSecondMomentForRouletteAndVarianceForSplitting) {
  // Numbers worked by hand: R = sqrt(avg(w² M / C)) · f, S likewise with the variance.
  auto stats = [](float moment, float variance, float cost) {
    ContinuationStats s;
    s.secondMoment = Color(moment);
    s.variance = Color(variance);
    s.cost = cost;
    return s;
  };
  // R = sqrt(2/2) · 0.5 = 0.5 ≤ 1: roulette by R.
  EXPECT_NEAR(earsFactor(Color(1.f), stats(2, 1, 2), 0.5f), 0.5f, 1e-6f);
  // R = sqrt(18/2) = 3, S = sqrt(8/2) = 2: split by S.
  EXPECT_NEAR(earsFactor(Color(1.f), stats(18, 8, 2), 1.f), 2.f, 1e-6f);
  // R = sqrt(8/2) = 2 but S = sqrt(0.5/2) = 0.5: neither.
  EXPECT_EQ(earsFactor(Color(1.f), stats(8, 0.5f, 2), 1.f), 1.f);
  // w = (3, 0, 0) and M = (6, 6, 6), C = 2: R = sqrt((9 · 6 / 2) / 3) = 3; S = sqrt((9 · 1.5 / 2) / 3) = 1.5.
  EXPECT_NEAR(earsFactor(Color(3, 0, 0), stats(6, 1.5f, 2), 1.f), 1.5f, 1e-6f);
  // No cost or no image error known: no decision (the estimator then uses classic roulette).
  EXPECT_EQ(earsFactor(Color(3.f), stats(6, 1.5f, 0), 2.f), 1.f);
  EXPECT_EQ(earsFactor(Color(3.f), stats(6, 1.5f, 2), 0.f), 1.f);
}

// A unit box split into cells of 1/2 (2 per side, 8 cells × 16 bins).
ContinuationCache unitBoxCache(int minSamples) {
  Bounds3 box;
  box.lo = Vec3(0.f);
  box.hi = Vec3(1.f);
  return ContinuationCache(box, 2, minSamples);
}

TEST(RouletteSplitting, CacheStatisticsFollowTheirDefinitionsInAnyOrder) {
  std::mt19937 rng(11);
  std::exponential_distribution<float> value(2.f);
  const Vec3 p(0.2f, 0.3f, 0.7f), up(0, 0, 1), down(0, 0, -1);
  // More than two of a thread's batches, so some are added to its sums
  // before update() and the rest by it.
  std::vector<Color> L(2 * ContinuationCache::RecordBatch + 300);
  std::vector<double> cost(L.size());
  for (size_t i = 0; i < L.size(); ++i) L[i] = Color(value(rng), value(rng), 0.f), cost[i] = double(1 + i % 7);

  // One cache records in order on this thread; another in reverse, spread
  // over TBB's threads (each its own log and sums).
  ContinuationCache inOrder = unitBoxCache(10), shuffled = unitBoxCache(10);
  const size_t slot = inOrder.slot(p, up);
  ContinuationCache::ThreadRecords* records = inOrder.threadRecords();
  for (size_t i = 0; i < L.size(); ++i) inOrder.record(records, slot, L[i], cost[i]);
  tbb::parallel_for(size_t(0), L.size(), [&](size_t k) {
    size_t i = L.size() - 1 - k;
    shuffled.record(shuffled.threadRecords(), slot, L[i], cost[i]);
  });
  inOrder.update();
  shuffled.update();
  const ContinuationStats* a = inOrder.lookup(slot);
  const ContinuationStats* b = shuffled.lookup(slot);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(std::memcmp(a, b, sizeof(ContinuationStats)), 0);  // bit for bit

  for (int c = 0; c < 3; ++c) {
    double mean = 0, moment = 0, variance = 0;
    for (const Color& l : L) mean += l[c], moment += double(l[c]) * l[c];
    mean /= double(L.size()), moment /= double(L.size());
    for (const Color& l : L) variance += (l[c] - mean) * (l[c] - mean);
    variance /= double(L.size());
    EXPECT_NEAR(a->mean[c], mean, 1e-6 * (mean + 1e-30)) << c;
    EXPECT_NEAR(a->secondMoment[c], moment, 1e-6 * (moment + 1e-30)) << c;
    EXPECT_NEAR(a->variance[c], variance, 1e-5 * (variance + 1e-30)) << c;
  }
  double meanCost = 0;
  for (double k : cost) meanCost += k;
  EXPECT_NEAR(a->cost, meanCost / double(cost.size()), 1e-6);

  // The bin of the rays arriving downwards holds nothing: it falls back to
  // its cell's total (which the up bin fills). Another cell knows nothing.
  const ContinuationStats* fallback = inOrder.lookup(inOrder.slot(p, down));
  ASSERT_TRUE(fallback);
  EXPECT_EQ(fallback->mean, a->mean);
  EXPECT_EQ(inOrder.lookup(inOrder.slot(Vec3(0.9f), up)), nullptr);
  // Below min_samples, a bin is unknown until more arrive (after update()).
  ContinuationCache sparse = unitBoxCache(400);
  for (size_t i = 0; i < 300; ++i) sparse.record(sparse.threadRecords(), slot, L[i], cost[i]);
  sparse.update();
  EXPECT_EQ(sparse.lookup(slot), nullptr);
  for (size_t i = 0; i < 300; ++i) sparse.record(sparse.threadRecords(), slot, L[i], cost[i]);
  EXPECT_EQ(sparse.lookup(slot), nullptr);
  sparse.update();
  EXPECT_NE(sparse.lookup(slot), nullptr);
}

TEST(RouletteSplitting, PixelEstimatesAreBoxMeansAndTheImageFactorItsDefinition) {
  const int W = 4, H = 3;
  PixelEstimates pixels(W, H);
  EXPECT_EQ(pixels.estimate(1, 1), Color(0.5f));  // before any pass
  auto value = [](int x, int y, int pass) { return Color(float(x + 2 * y + pass), 1.f, 0.5f * float(x)); };
  auto rays = [](int x, int y) { return double(3 + x + y); };
  const int Passes = 5;
  std::vector<double> passError, passCost;
  for (int pass = 0; pass < Passes; ++pass) {
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) pixels.record(x, y, value(x, y, pass), rays(x, y));
    // E and C of this pass, against the estimates it was recorded with.
    double error = 0, cost = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        Color P = pixels.estimate(x, y);
        Color e = (value(x, y, pass) - P) / (P + Color(0.01f));
        error += meanOf(e * e), cost += rays(x, y);
      }
    passError.push_back(error), passCost.push_back(cost);
    pixels.update();
    // The factor of passes ⌊n/2⌋ … n − 1 of the n so far (12 samples each:
    // 10 per million leaves none out).
    double E = 0, C = 0;
    for (int k = (pass + 1) / 2; k <= pass; ++k) E += passError[size_t(k)], C += passCost[size_t(k)];
    EXPECT_NEAR(pixels.imageFactor(), std::sqrt(C / E), 1e-5 * std::sqrt(C / E)) << pass;
  }
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      Color sum(0.f);
      int n = 0;
      for (int yy = std::max(0, y - 1); yy <= std::min(H - 1, y + 1); ++yy)
        for (int xx = std::max(0, x - 1); xx <= std::min(W - 1, x + 1); ++xx)
          for (int pass = 0; pass < Passes; ++pass) sum += value(xx, yy, pass) / float(Passes), ++n;
      Color expected = sum / float(n / Passes), got = pixels.estimate(x, y);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-5f * (1 + expected[c])) << x << " " << y;
    }
}

// 10 per million of a pass's errors are left out of E: at 200 000 pixels,
// the two largest. One pixel far off and one a little off are both left
// out; the rest have the same error.
TEST(RouletteSplitting, ImageErrorLeavesOutItsLargestTenPerMillion) {
  const int W = 500, H = 400;
  PixelEstimates pixels(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) pixels.record(x, y, Color(0.5f), 1.0);
  pixels.update();  // P = 0.5 everywhere
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      float v = x == 7 && y == 3 ? 1e6f : x == 9 && y == 300 ? 2.f : 1.5f;
      pixels.record(x, y, Color(v), 2.0);
    }
  pixels.update();
  // Each kept sample: ((1.5 − 0.5) / 0.51)², cost 2.
  double e = (1.0 / 0.51) * (1.0 / 0.51);
  EXPECT_NEAR(pixels.imageFactor(), std::sqrt(2.0 / e), 1e-5);
}

// The path estimator under a cache the test fills: slots by parity ask for
// the largest split or the smallest survival, both clamped (and the split
// capped by the path's product of factors). Nothing updates it during the
// render.
// What it records goes to `learner` (same grid), if given.
class FixedCachePath final : public PixelIntegrator {
 public:
  // learned false: the warm-up, where classic roulette decides everywhere.
  FixedCachePath(PathTracerSettings s, ContinuationCache& cache, ContinuationCache* learner = nullptr,
                 bool learned = true)
      : estimator_(s), cache_(cache), learner_(learner ? *learner : cache), learned_(learned) {}
  std::string splitRefusal() const override { return ""; }

 protected:
  Color Li(const Ray&, const Scene&, Sampler&, uint64_t&) const override { return Color(0.f); }
  Color pixelLi(int, int, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override {
    RrsView view{&cache_, learner_.threadRecords(), estimator_.settings().rrs, learned_, Color(1.f), 1.f};
    return estimator_.Li(ray, scene, sampler, rays, nullptr, &view);
  }

 private:
  PathEstimator estimator_;
  ContinuationCache& cache_;
  ContinuationCache& learner_;
  bool learned_;
};

// Even slots: mean 10⁴ with variance 10⁸ (both rules split 20-fold), or
// all slots so if `allSplit`; odd ones: 10⁻⁶ without variance (both keep 1
// path in 20).
ContinuationCache wrongCache(const Scene& scene, bool allSplit = false) {
  ContinuationCache cache(scene.bounds(), 4, 1);
  ContinuationCache::ThreadRecords* records = cache.threadRecords();
  for (size_t slot = 0; slot < cache.slotCount(); ++slot)
    for (float v : {2e4f, 0.f}) cache.record(records, slot, Color(slot % 2 == 0 || allSplit ? v : 1e-6f), 3.0);
  cache.update();
  return cache;
}

std::unique_ptr<Film> renderWithWrongCache(const SceneFile& sf, uint64_t spp, const char* params) {
  ContinuationCache cache = wrongCache(*sf.scene);
  Params p(YAML::Load(params), "<test>", "integrator");
  FixedCachePath integrator(PathTracerSettings::read(p), cache);
  auto film = std::make_unique<Film>(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = 9;
  options.budget.spp = spp;
  renderLoop(*sf.scene, integrator, *film, sf.sampler, options);
  return film;
}

// The furnace (albedo 0.5, emission 1): L = 2 exactly, every pixel.
TEST(RouletteSplitting, WrongCacheLeavesTheFurnaceUnbiased) {
  SceneFile sf = loadSceneFromString(furnaceScene(0.5f), "furnace.yaml");
  for (const char* params :
       {"{rrs: adrrs}", "{rrs: ears}", "{rrs: adrrs, rrs_split_light: false}", "{rrs: ears, rrs_split_light: false}"}) {
    auto film = renderWithWrongCache(sf, 256, params);
    EXPECT_EQ(film->nonFiniteCount(), 0u) << params;
    EXPECT_TRUE(meanMatches(*film, 2.0, 1e-3)) << params;
  }
}

// The light samples split (and rouletted) with the continuation carry 1/q
// as it does: EARS from the first hit on, where light sampling is most of
// the Cornell box's light. Seen failing (z > 10 in every region) with the
// light samples left at full weight.
TEST(RouletteSplitting, WrongCacheLeavesCornellBoxUnbiased) {
  SceneFile sf = loadShippedScene("cornell-box", 24, 24);
  auto reference = regionMeans(*renderScene(sf, {"path", "{}", 1024, 100}), 3, 3);
  for (const char* params : {"{rrs: adrrs}", "{rrs: ears}"}) {
    auto film = renderWithWrongCache(sf, 512, params);
    EXPECT_EQ(film->nonFiniteCount(), 0u) << params;
    EXPECT_EQ(compareRegions(regionMeans(*film, 3, 3), reference, 1e-3), "") << params;
  }
}

// A guide whose distribution depends on where it was prepared: a cosine
// lobe about the direction from the scene's centre to the point.
class PointDependentGuide final : public DirectionGuide {
 public:
  explicit PointDependentGuide(Vec3 centre) : DirectionGuide(0.5f), centre_(centre) {}
  float pdf(const Vec3& wi) const override { return cosineHemispherePdf(frame_.toLocal(wi).z); }
  Vec3 sample(Vec2 u, float* pdf) const override {
    Vec3 local = sampleCosineHemisphere(u);
    *pdf = cosineHemispherePdf(local.z);
    return frame_.toWorld(local);
  }

 protected:
  bool prepareAt(const SurfaceInteraction& si, const BSDF&) override {
    Vec3 axis = si.p - centre_;
    if (!(glm::dot(axis, axis) > 0)) return false;
    frame_ = Frame(glm::normalize(axis));
    return true;
  }

 private:
  Vec3 centre_;
  Frame frame_;
};

// Checks every non-delta direction a path scattered into: its recorded
// density is the mixture's, with the guide prepared at the vertex itself.
class MixtureDensityChecker final : public PathObserver {
 public:
  explicit MixtureDensityChecker(Vec3 centre) : fresh_(centre) {}
  void shaded(const SurfaceInteraction&, const BSDF*, const Color&, const Color&) override {}
  void splitLight(const Color&) override {}
  void scattered(const SurfaceInteraction& si, const PathState& s) override {
    if (s.prevDelta) return;
    BSDF bsdf(si);
    float expected = bsdf.pdf(si.wo, s.ray.d);
    if (fresh_.prepare(si, bsdf)) expected = fresh_.mixturePdf(expected, s.ray.d);
    (s.nesting > 0 ? branches : lines)++;
    if (std::abs(s.prevPdf - expected) > 1e-4f * expected) ++mismatches;
  }
  int branches = 0, lines = 0, mismatches = 0;

 private:
  PointDependentGuide fresh_;
};

// A split's continuations are traced one after another, and tracing one
// prepares the guide at its own later vertices: each must have drawn its
// direction from the guide as prepared at the split's vertex (so all are
// drawn before any is traced, path_splitting.cpp), or it would be weighed
// against NEE with a density its light samples did not see. Seen failing
// (hundreds of mismatches) when each continuation draws just before it is traced.
TEST(RouletteSplitting, SplitContinuationsDrawFromTheGuideAtTheirVertex) {
  SceneFile sf = loadShippedScene("cornell-box", 8, 8);
  const Scene& scene = *sf.scene;
  ContinuationCache cache = wrongCache(scene, true);  // splits 20-fold everywhere
  Params p(YAML::Load("{rrs: adrrs, max_depth: 6}"), "<test>", "integrator");
  PathEstimator estimator(PathTracerSettings::read(p));
  estimator.preprocess(scene, 1);
  const Vec3 centre = 0.5f * (scene.bounds().lo + scene.bounds().hi);
  PointDependentGuide guide(centre);
  MixtureDensityChecker checker(centre);
  RrsView view{&cache, cache.threadRecords(), RrsMethod::Adrrs, true, Color(1.f), 1.f};
  IndependentSampler sampler(7);
  uint64_t rays = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      sampler.start(uint64_t(y * 8 + x), 0);
      Camera::FilmSample at = scene.camera.sampleFilm(x, y, sampler.get2D());
      PathState s;
      s.ray = scene.camera.generateRay(at.raster);
      s.prevPoint = s.ray.o;
      PathContext c{scene, sampler, 6, true, sampler.dimension(), &guide, nullptr, &view};
      estimator.trace(s, c, rays, &checker);
    }
  EXPECT_GT(checker.branches, 1000);
  EXPECT_GT(checker.lines, 64);
  EXPECT_EQ(checker.mismatches, 0) << "of " << checker.branches + checker.lines << " directions";
}

// What a render of the furnace (albedo 0.5, emission 1) under `params`
// teaches a fresh cache (`learned`: the fixed cache's factors, 20-fold
// splits everywhere; else classic roulette decides, as in the warm-up).
struct FurnaceRecords {
  ContinuationStats all;
  int64_t count = 0;
  double samples = 0;  // camera samples rendered
  std::unique_ptr<Film> film;
};
FurnaceRecords recordFurnace(const std::string& params, bool learned, uint64_t seed, uint64_t spp) {
  SceneFile sf = loadSceneFromString(furnaceScene(0.5f), "furnace.yaml");
  ContinuationCache fixed = wrongCache(*sf.scene, true);
  ContinuationCache learner(sf.scene->bounds(), 4, 1);
  Params p(YAML::Load(params), "<test>", "integrator");
  FixedCachePath integrator(PathTracerSettings::read(p), fixed, &learner, learned);
  FurnaceRecords r;
  r.film = std::make_unique<Film>(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = seed;
  options.budget.spp = spp;
  renderLoop(*sf.scene, integrator, *r.film, sf.sampler, options);
  learner.update();
  r.all = learner.overall(&r.count);
  r.samples = double(r.film->width() * r.film->height()) * double(spp);
  return r;
}

// What a continuation records, where every number is known: in the furnace
// (emission 1 everywhere, albedo a = 0.5, cosine-sampled so f cos/p = a
// exactly), without NEE or classic roulette, paths of at most 3 segments,
// and ADRRS told to split 20-fold everywhere: its first vertex (v0) is not
// split; v1 is, 20 times, each continuation one segment to an emitter. So
// per camera sample v0 records a + 20 · (a/20) · a = 0.75 at a cost of 21
// rays, and v1 records 20 times a = 0.5 at 1 ray each. A continuation
// recorded before its line ends, or divided by β rather than β/q, is off.
TEST(RouletteSplitting, ContinuationsRecordWhatTheyBringBackAndCost) {
  FurnaceRecords r = recordFurnace("{rrs: adrrs, nee: false, rr: false, max_depth: 3}", true, 3, 2);
  EXPECT_EQ(double(r.count), 21 * r.samples);
  // Float rounding of a few products per value: 1e-5 relative is generous.
  EXPECT_NEAR(r.all.mean.g, (0.75 + 20 * 0.5) / 21, 1e-5);
  EXPECT_NEAR(r.all.secondMoment.g, (0.75 * 0.75 + 20 * 0.25) / 21, 1e-5);
  EXPECT_NEAR(r.all.cost, (21.0 + 20.0) / 21, 1e-5);
  // The image, meanwhile, is the furnace's 1 + a + a² exactly.
  EXPECT_NEAR(r.film->image().pixels[17].g, 1.75f, 1e-5f);
}

// The same with the light samples split too (rrs_split_light, the default):
// each of v1's 20 continuations takes its own light sample and records it
// with what its direction brings back, a · Le = 0.5 in expectation, for a
// shadow ray and a continuation ray; v0 records 0.5 + a · 0.5 = 0.75, for
// its own two rays and its 20 continuations' 40. Seen failing with a
// branch's light samples left out of its record (mean 0.29) and with
// continuation 0's light samples counted per unit of β, not β/q (0.5006
// against 0.5119, 6 standard errors 0.003).
TEST(RouletteSplitting, SplitLightSamplesAreRecordedWithTheirContinuations) {
  FurnaceRecords r = recordFurnace("{rrs: adrrs, rr: false, max_depth: 3}", true, 3, 4);
  ASSERT_EQ(double(r.count), 21 * r.samples);
  const double standardError = std::sqrt(r.all.variance.g / double(r.count));
  EXPECT_NEAR(r.all.mean.g, (0.75 + 20 * 0.5) / 21, 6 * standardError);
  // Every light sample from inside the sphere reaches it: 2 rays a record
  // at v1, 42 at v0.
  EXPECT_NEAR(r.all.cost, (42.0 + 20 * 2.0) / 21, 1e-6);
  EXPECT_EQ(r.film->nonFiniteCount(), 0u);
}

// Where classic roulette decides (the warm-up, and cells the cache knows
// nothing of), a continuation it kills is not recorded, and one it keeps is
// recorded per unit of the β/p it carries, as a learned q = p would be
// (iRath96/ears records only the continuations taken). The furnace (albedo
// 0.5, emission 1), one bounce: roulette at the first vertex keeps the path
// with p = 0.5 and the continuation brings back exactly a · Le, so every
// record is 0.5 at a cost of 1 ray, and about half the paths record. Seen
// failing with the killed ones recorded as zeros and the kept ones per unit
// of β (second moment 0.5, cost 0.5): the mean was right, but EARS's factor
// came out 1/p too large wherever classic roulette had taught the cache.
TEST(RouletteSplitting, ClassicRouletteRecordsOnlyTheContinuationsItKeeps) {
  FurnaceRecords r = recordFurnace("{rrs: ears, nee: false, rr: true, rr_depth: 1, max_depth: 2}", false, 5, 4);
  EXPECT_NEAR(r.all.mean.g, 0.5, 1e-6);
  EXPECT_NEAR(r.all.secondMoment.g, 0.25, 1e-6);
  EXPECT_NEAR(r.all.cost, 1.0, 1e-9);
  // Binomial(samples, 1/2): within 5 standard deviations.
  EXPECT_NEAR(double(r.count), r.samples / 2, 5 * std::sqrt(r.samples / 4));
}

// With rrs_split_light (the default) a vertex's record is its whole
// reflected-radiance estimate, its light samples included, as the authors
// record theirs: in the furnace with one bounce its mean is a · Le = 0.5,
// and its cost the shadow ray's and the continuation's. Without, the
// continuation alone: the BSDF sample's MIS-weighted share of the 0.5, one
// ray. Classic roulette decides (rr off: every continuation kept). Seen
// failing with the light samples left out of a split-light record.
TEST(RouletteSplitting, RecordsHoldTheLightSamplesThatAreSplit) {
  for (bool splitLight : {true, false}) {
    std::string yaml = std::string("{rrs: ears, rr: false, max_depth: 2, rrs_split_light: ") +
                       (splitLight ? "true" : "false") + "}";
    FurnaceRecords r = recordFurnace(yaml, false, 7, 16);
    ASSERT_EQ(double(r.count), r.samples) << yaml;
    const double standardError = std::sqrt(r.all.variance.g / double(r.count));
    if (splitLight) {
      EXPECT_NEAR(r.all.mean.g, 0.5, 5 * standardError) << yaml;
      EXPECT_GT(r.all.cost, 1.5) << yaml;
    } else {
      EXPECT_LT(r.all.mean.g, 0.5 - 5 * standardError) << yaml;
      EXPECT_EQ(r.all.cost, 1.0) << yaml;
    }
  }
}

// The cache and the pixel estimates learn between passes, from exact sums
// and per-pixel records: the same bits with one thread or two.
TEST(RouletteSplitting, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile s = loadShippedScene("cornell-box", 32, 32);
  for (const char* params : {"{rrs: ears, rrs_warmup: 2, rrs_min_samples: 8}", "{rrs: adrrs, rrs_warmup: 2}"}) {
    Image one = renderScene(s, {"path", params, 8, 42, 1})->image();
    Image two = renderScene(s, {"path", params, 8, 42, 2})->image();
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << params;
    // … and the learned factors changed the image: it differs from the
    // same settings kept in their warm-up (classic roulette) throughout.
    std::string warmUp = std::string(params).substr(0, std::strlen(params) - 1) + ", rrs_warmup: 100}";
    warmUp.replace(warmUp.find("rrs_warmup: 2, "), std::strlen("rrs_warmup: 2, "), "");
    Image classic = renderScene(s, {"path", warmUp, 8, 42, 1})->image();
    EXPECT_NE(std::memcmp(one.pixels.data(), classic.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << params;
  }
}

TEST(RouletteSplitting, RefusesWhatCannotSplitOrLearn) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"path", "{rrs: ears, engine: wavefront}"},
      {"path", "{rrs: ears, first_bounce_samples: 2}"},
      {"path", "{rrs: adrrs, mis: variance_aware}"},
      {"path", "{rrs: ears, max_depth: -1}"},
      {"path", "{rrs_warmup: 2}"},  // a key of adrrs and ears only
      {"guided", "{rrs_cells: 4}"},
  };
  for (const auto& [integrator, params] : refused)
    EXPECT_THROW(renderScene(scene, {integrator, params, 1, 1}), ConfigError) << integrator << " " << params;
  // What it learned from earlier passes' numbers must not be correlated
  // with a later pass's: low-discrepancy samplers are refused.
  SceneFile sobol = loadShippedScene("cornell-box", 8, 8, "sampler: {type: sobol}");
  for (const char* params : {"{rrs: ears}", "{rrs: adrrs}", "{mis: variance_aware}"})
    EXPECT_THROW(renderScene(sobol, {"path", params, 1, 1}), std::invalid_argument) << params;
  EXPECT_NO_THROW(renderScene(sobol, {"path", "{}", 1, 1}));
  RenderSpec adaptive{"path", "{rrs: ears}", 4, 1};
  adaptive.adaptive.enabled = true;
  EXPECT_ANY_THROW(renderScene(scene, adaptive));
}

}  // namespace
}  // namespace lb::test
