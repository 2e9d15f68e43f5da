#pragma once
// The unidirectional path estimator, shared by the `path` integrator (and its
// wavefront engine), the irradiance cache's records and primary-sample-space
// MLT: unidirectional path tracing with the switches of the classic comparisons
// (Veach 1997 ch. 9; pbrt-v4 §13.4; the lectures' "simplest Monte Carlo path
// tracer" and "efficient implementation"):
//
//   sampling   bsdf | cosine | uniform   how non-delta bounces choose directions
//   nee        true | false              next-event estimation (light samples at each vertex)
//   mis        power | balance | none | one_sample | variance_aware
//                                        how NEE and emitter hits are combined
//   pilot_passes, factor_block           variance_aware: its pilot and pooling (variance_aware_mis.h)
//   light_selection_probability q        one_sample: the chance of taking the light sample
//   emission_selection p                 emit-vs-reflect: end at an emitter with chance p
//   shadow_rays N, first_bounce_samples M  splitting
//   light_selection scene | uniform | power | spatial
//   engine     single_ray | wavefront    one path at a time, or rays in streams (wavefront.h)
//   mis_compensation                     NEE from lights' MIS-compensated densities (core/lights/light.h)
//   max_depth, rr, rr_depth              path length and roulette (path_length.h)
//   rrs        classic | adrrs | ears     roulette and splitting: rr's, or learned (roulette_splitting.h)
//   rrs_warmup, rrs_cells, rrs_min_samples  adrrs | ears: the passes before learned factors, the cache's grid
//   rrs_split_light                      adrrs | ears: split the vertex's light samples too, or the continuation only
//   regularize, regularize_roughness, regularize_exponent  path-space regularization (regularization.h)
//   mnee, mnee_max_chain                 manifold next-event estimation (manifold_nee.cpp)
//   sms, sms_trials                      specular manifold sampling (manifold_nee.cpp)
// (these are the `path` integrator's keys, read by PathTracerSettings::read)
//
// With nee on and mis none, emitters hit after a non-delta bounce are ignored
// (pure NEE); with nee off, only hits count, so delta lights are invisible.
//
// Estimators (each cited where it is computed in path_tracer.cpp):
//  * multi-sample MIS with N light samples and M (first vertex) or 1 BSDF
//    samples: weights w_i = h(n_i p_i, n_j p_j), Veach 1997 Eq. 9.12-9.13;
//  * variance-aware MIS (Grittmann et al. 2019): the balance heuristic over
//    c_i n_i p_i, c_i learned per pixel block and path length from pilot
//    passes (variance_aware_mis.h);
//  * learned roulette and splitting (ADRRS, Vorba & Křivánek 2016; EARS,
//    Rath et al. 2022): n = ⌊q + u⌋ continuations, each weighted 1/q, with
//    q from a cache learned between passes (roulette_splitting.h,
//    path_splitting.cpp);
//  * one-sample MIS: one strategy per vertex, the light's with probability q;
//    its estimate is w_L f/(q p_L) or w_f f/((1 − q) p_f) with the balance
//    heuristic over the selection probabilities, w_i = c_i p_i / Σ c_k p_k
//    (Veach 1997 Eq. 9.15 and §9.2.4). The path always continues with the
//    BSDF direction; the emitter it reaches counts only if that vertex chose
//    the BSDF strategy. Weights sum to 1: w_L + w_f = 1.
//  * manifold next-event estimation (Hanika, Droske & Fascione 2015): at
//    a non-delta vertex one more light point y, sampled by area, connects
//    through the smooth refracting surfaces its straight segment crosses
//    (integrators/manifold/specular_chain.h); the paths it finds (1 …
//    mnee_max_chain refractions between a non-delta vertex and an area
//    light) are its own, so BSDF sampling's hits of them count zero;
//  * emit vs reflect: at an emitter where the path could continue, the
//    (weighted) emission is taken with probability p and the path ends, else
//    the emission is skipped and β is divided by 1 − p (Russian roulette over
//    the two terms of the rendering equation).
//
// Sampler dimensions (core/sampler.h): the camera ray uses 0-1 (pixel
// jitter). Vertex v (the camera ray's hit is v = 0) of branch b (b < M; only
// the first vertex branches) starts at dimension
//     entry + (v·M + b)·S,  S = 6 + 4·N,
// where entry is sampler.dimension() when the path starts (2 for camera
// paths), and the vertex's slots are
//     0 emit-vs-reflect choice   1 one-sample strategy choice
//     2 + 4i .. 5 + 4i  shadow ray i (light, pick, 2-D point)
//     2 + 4N lobe   3 + 4N .. 4 + 4N direction   5 + 4N roulette (rrs:
//                   adrrs | ears, learned: the u of n = ⌊q + u⌋)
//     6 + 4N        (rrs: adrrs | ears only) the key of the split's other
//                   continuations, which draw from samplers of their own
//     then, with mnee, 4 more: its light, pick, and 2-D point; with sms, 5:
//                   those and the key of its seeds' own random numbers
// At the first vertex, slots 0, 1 and the shadow rays are branch 0's; each
// branch b draws its own lobe, direction and roulette. So a low-discrepancy
// sampler gives every vertex the same dimensions on every path. Draws go
// forward within a path (the independent sampler skips ahead, cheaply; a
// step back re-seeds it), except where a learned split's u is drawn before
// the vertex's direction (path_splitting.cpp).
#include <memory>
#include <optional>
#include "core/bsdfs/bsdf.h"
#include "core/params.h"
#include "core/spatial_light_sampler.h"
#include "core/scene.h"
#include "core/rng.h"
#include "core/sampler.h"
#include "core/bsdfs/regularization.h"
#include "integrators/path_estimator/direction_guide.h"
#include "integrators/path_estimator/hemisphere.h"
#include "integrators/path_estimator/roulette_splitting.h"
#include "integrators/path_estimator/variance_aware_mis.h"
#include "integrators/manifold/specular_chain.h"
#include "integrators/path_length.h"

namespace lb {

enum class MisHeuristic { None, Balance, Power, OneSample, VarianceAware };
enum class SmsMode { Off, Unbiased, Biased };
enum class LightChoice { Scene, Uniform, Power, Spatial };

struct PathTracerSettings {
  DirectionSampling sampling = DirectionSampling::Bsdf;
  bool nee = true;
  MisHeuristic mis = MisHeuristic::Power;
  float lightSelectionProbability = 0.5f;
  float emissionSelection = 0;  // 0: emission always counted
  int shadowRays = 1;
  int firstBounceSamples = 1;
  LightChoice lightSelection = LightChoice::Scene;
  bool wavefront = false;  // engine: wavefront (wavefront.h) instead of one ray at a time
  bool misCompensation = false;  // NEE from lights' MIS-compensated densities (core/lights/light.h)
  int pilotPasses = 1;           // mis: variance_aware: passes that learn its factors
  int factorBlock = 8;           // mis: variance_aware: pixels per side of the blocks its moments pool
  RegularizationSettings regularization;  // regularize: path-space regularization (regularization.h)
  RrsMethod rrs = RrsMethod::Classic;  // roulette and splitting (roulette_splitting.h)
  int rrsWarmup = 4;             // rrs: adrrs | ears: passes of classic roulette before the learned factors
  int rrsCells = 8;              // … the cache's cells along the scene's longest side
  int rrsMinSamples = 64;        // … continuations a cache bin needs before it is used
  bool rrsSplitLight = true;     // … the light samples are split with the continuation (else taken once)
  bool mnee = false;             // manifold next-event estimation (manifold_nee.cpp)
  SmsMode sms = SmsMode::Off;    // specular manifold sampling (manifold_nee.cpp)
  int smsTrials = 64;            // sms: at most this many seeds per estimate of 1/p (unbiased), or exactly (biased)
  ManifoldSettings manifold;     // mnee, sms: the solver's settings (mnee_max_chain; 1 for sms)
  PathLength length;

  // Without `directionKeys`, the keys that change how directions are drawn
  // (sampling, first_bounce_samples, engine) are not read, so not accepted:
  // the guided integrator draws its own (integrators/guided/guided.h).
  static PathTracerSettings read(Params& p, bool directionKeys = true);
  // Dimensions one vertex of one branch takes (S above), and where its
  // direction sampling (lobe, direction, roulette) begins.
  uint32_t vertexStride() const { return manifoldSlot() + (mnee ? 4 : sms != SmsMode::Off ? 5 : 0); }
  uint32_t manifoldSlot() const { return (rrs == RrsMethod::Classic ? 6 : 7) + 4 * uint32_t(shadowRays); }
  uint32_t scatterSlot() const { return 2 + 4 * uint32_t(shadowRays); }
};

// One-sample MIS weights over (light, BSDF) chosen with probabilities (q, 1 − q):
// the balance heuristic over c_i p_i (Veach 1997 Eq. 9.15).
struct OneSampleWeights {
  float light, bsdf;
};
OneSampleWeights oneSampleMisWeights(float q, float lightPdf, float bsdfPdf);

// Where a path is between vertices: the ray to trace and what the vertex it
// left knows about the direction it chose (for the MIS weight of an emitter
// that ray may hit).
struct PathState {
  Ray ray;
  Color beta{1.f};
  float etaScale = 1;            // removes radiance's 1/η² scaling from roulette decisions
  bool prevDelta = true;         // the camera "bounce" is a delta event: emission counts in full
  float prevPdf = 0;             // solid-angle pdf of the direction that generated `ray`
  float prevBsdfCount = 1;       // directions the previous vertex sampled (M at the first)
  bool prevLightChosen = false;  // one-sample MIS: the previous vertex took the light strategy
  Vec3 prevPoint{0.f};
  int vertex = 0;                // the vertex `ray` is about to reach (0: the camera ray's hit)
  int branch = 0;                // which of the first vertex's M directions this path took
  float splitProduct = 1;        // rrs: the product of the roulette and split factors so far
  int nesting = 0;               // rrs: depth of recursion (continuations 1 … n − 1 of a split are one deeper)
  bool pastNonDelta = false;     // the path has scattered at a non-delta vertex (regularize: where it applies)
  int manifoldChain = -1;        // mnee: refractions since the last non-delta vertex (−1: none since, or not only)
};

// What a path's vertices share: the scene, the sampler (started for the
// path's pixel and sample), the length limit and where its dimensions begin;
// and, for the `guided` integrator, the learned direction distribution
// (direction_guide.h), which shadeVertex prepares at each vertex and weighs
// light samples against. A caller that sets it must pass it to scatter() as
// well, or directions would be drawn without it and weighted as if with it.
struct PathContext {
  const Scene& scene;
  Sampler& sampler;
  int maxDepth;
  bool firstEmission;
  uint32_t entryDimension;
  DirectionGuide* guide = nullptr;
  const VarianceAwareView* varianceAware = nullptr;  // mis: variance_aware: this sample's factors
  const RrsView* rrs = nullptr;  // rrs: adrrs | ears: the cache and this sample's pixel
  const Regularization* regularization = nullptr;  // regularize: this pass's rough twins
};

// A light sample waiting for its visibility test: `contribution` (weighted,
// times β) counts if `ray` is unoccluded.
struct ShadowRequest {
  Ray ray;
  Color contribution;
  float unweighted = 0;  // mis: variance_aware pilots: the luminance of the sample's estimate before MIS
  int segments = 0;      // … and its path length
  bool tested = false;   // sms: biased: `contribution` is already the visible solutions' sum; trace nothing
};

// Watches a path vertex by vertex, for a caller that learns from it (the
// guided integrator records each scattering vertex and what came back to it)
// without a copy of the loop (issue 39).
class PathObserver {
 public:
  virtual ~PathObserver() = default;
  // Vertex `si` was shaded (or the ray escaped: `si` unset, `bsdf` null):
  // `emitted` is the emission its segment reached, MIS-weighted and times β;
  // `added` all it added to the estimate, the unoccluded light samples too;
  // `bsdf` is null where the path ends.
  virtual void shaded(const SurfaceInteraction& si, const BSDF* bsdf, const Color& emitted, const Color& added) = 0;
  // rrs_split_light: a split's further continuation took its own light
  // samples at the vertex last shaded, adding `added` (times β) to the
  // estimate before any of the split's continuations is traced.
  virtual void splitLight(const Color& added) = 0;
  // The path scattered at `si` into `s.ray` (`s.beta`, `s.prevPdf`, `s.prevDelta` updated).
  // With first_bounce_samples > 1 the branches are reported depth first, one
  // whole branch after another: an observer that keeps per-path state must
  // tell them apart by s.branch. So are rrs's split continuations: those
  // traced at once (PathState::nesting one deeper) come before the one the
  // line goes on with, whose vertices come last (guided's recorder,
  // vertex_recorder.h, keeps each record's ancestors apart this way).
  virtual void scattered(const SurfaceInteraction& si, const PathState& s) = 0;
};

class PathEstimator {
 public:
  static constexpr int MaxShadowRays = 64;
  static constexpr int MaxShadowRequests = MaxShadowRays + 1;  // and mnee's

  explicit PathEstimator(PathTracerSettings s) : settings_(s) {}
  // Light selection tables (light_selection: uniform | power | spatial);
  // `seed` seeds the spatial table's estimates. Without it, the scene's rule.
  void preprocess(const Scene& scene, uint64_t seed);

  // Radiance arriving along `ray` over paths of at most `maxSegments`
  // segments. Without `firstEmission`, the emission of the first surface hit
  // (or of the environment, if the ray escapes) is left out: the caller counts
  // that light itself (the irradiance cache's records gather only indirect
  // light). `firstHitDistance`, if given, receives the first hit's distance
  // (infinity if the ray escapes). The path's dimensions start at
  // sampler.dimension(); the sampler is left at no particular dimension, so a
  // caller restarts it (start()) before drawing again.
  Color incidentRadiance(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays, int maxSegments,
                         bool firstEmission, float* firstHitDistance = nullptr,
                         const VarianceAwareView* varianceAware = nullptr, const RrsView* rrs = nullptr,
                         const Regularization* regularization = nullptr) const;
  // A camera path: all of max_depth, emission of the first hit included.
  // `varianceAware`: this pixel's factors (mis: variance_aware); `rrs`: the
  // roulette and splitting cache and this pixel (rrs: adrrs | ears). The
  // path integrator owns both.
  Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays,
           const VarianceAwareView* varianceAware = nullptr, const RrsView* rrs = nullptr,
           const Regularization* regularization = nullptr) const {
    return incidentRadiance(ray, scene, sampler, rays, settings_.length.maxSegments(), true, nullptr, varianceAware,
                            rrs, regularization);
  }

  // The estimator, one vertex at a time, shared by the single-ray loop and
  // the wavefront engine (integrators/path/wavefront.h) so both compute the
  // same thing:
  //  shadeVertex: what the ray of `s` found (`hit`, `si`): its emission is
  //    added to L, its light samples are written to `shadows` (their number is
  //    returned; the caller adds each contribution whose ray is unoccluded);
  //    `bsdf` is set if the path may go on from `si`.
  //  scatter: the next direction from the vertex's dimension slots; updates
  //    `next` (β, pdfs, ray); false if the path ends (absorbed, roulette).
  //    With a `guide` that shadeVertex prepared (and found active), the
  //    direction comes from its mixture with the BSDF: the lobe number picks
  //    the component (below bsdf_fraction: the BSDF, rescaled as its lobe
  //    number), the 2-D number places the direction.
  int shadeVertex(PathState& s, bool hit, const SurfaceInteraction& si, const PathContext& c, Color& L,
                  ShadowRequest* shadows, std::optional<BSDF>& bsdf) const;
  //  lightSamples: shadeVertex's light samples at `si` (after its emission),
  //    also drawn for each of a split's further continuations (rrs).
  //    `guided`: c.guide was prepared at `si` and is active.
  int lightSamples(PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c, bool guided,
                   ShadowRequest* shadows) const;
  bool scatter(PathState& next, const SurfaceInteraction& si, const BSDF& bsdf, Sampler& sampler, uint32_t slots,
               const DirectionGuide* guide = nullptr, bool roulette = true) const;
  // Classic roulette on the direction scatter() just took (its last
  // sampler dimension); `survival`, if given, receives the probability.
  bool survivesRoulette(PathState& next, Sampler& sampler, uint32_t slots, float* survival = nullptr) const;
  // rrs: adrrs | ears: the factor q for the continuation from the vertex in
  // the cache's `cacheSlot` (before the caps on nesting and on the path's
  // product of factors); none where classic roulette decides instead.
  std::optional<float> splitFactor(const PathState& s, size_t cacheSlot, const BSDF& bsdf, const RrsView& r) const;
  // The first dimension of the vertex `s` is about to reach (layout above).
  uint32_t vertexBase(const PathState& s, const PathContext& c) const {
    return c.entryDimension +
           (uint32_t(s.vertex) * uint32_t(settings_.firstBounceSamples) + uint32_t(s.branch)) * settings_.vertexStride();
  }
  const PathTracerSettings& settings() const { return settings_; }
  // The single-ray loop from `state` under `ctx` (its guide, if any, draws
  // the directions), reporting each vertex to `observer` if given.
  Color trace(PathState& state, const PathContext& ctx, uint64_t& rays, PathObserver* observer) const {
    return trace(state, ctx, rays, nullptr, observer);
  }

 private:
  Color trace(PathState& state, const PathContext& ctx, uint64_t& rays, float* firstHitDistance,
              PathObserver* observer) const;
  float misWeight(float nThis, float pdfThis, float nOther, float pdfOther) const;
  // Variance-aware MIS: technique t's factor for paths of `length` segments (else 1).
  static float techniqueFactor(const PathContext& c, int length, MisTechnique t) {
    return c.varianceAware ? c.varianceAware->factor(length, t) : 1.f;
  }
  // rrs: a continuation of a line (the single-ray loop's path) waiting for
  // the line to end, when what it brought back is known: L − `before`.
  // What it brought back, per unit throughput, is `direct` + (L − `before`) / `beta`.
  struct Continuation {
    size_t slot;         // the vertex's in the cache
    Color beta, before;  // the continuation's throughput, L when it began
    Color direct;        // its light samples at the vertex, per unit throughput
    uint64_t rays;       // rays traced when it began (its light samples' included)
  };
  static constexpr int MaxRecordedVertices = 64;  // later vertices of a line go unrecorded
  static constexpr int MaxNesting = 8;            // splits below this many go unsplit (q ≤ 1)
  static constexpr float MaxSplitProduct = 64;    // a path's factors multiply to at most this
  // n = ⌊q + u⌋ is below this (q ≤ 20, and q + u may round up to 21 in float).
  static constexpr int MaxSplitContinuations = int(MaxSplitFactor) + 2;
  // rrs, at a vertex, before its light samples are traced (they are split
  // with the continuation unless rrs_split_light is false): the learned
  // factor q and the number n = ⌊q + u⌋ of estimates of its reflected
  // radiance (light samples and continuation), or classic roulette.
  struct SplitDecision {
    size_t slot = 0;       // the vertex's in the cache
    bool learned = false;  // false: classic roulette decides, after the direction
    float q = 1, u = 0;
    int n = 1;
  };
  SplitDecision decideSplit(const PathState& s, const SurfaceInteraction& si, const BSDF& bsdf,
                            const PathContext& c) const;
  // Roulette and splitting at `si` (path_splitting.cpp) as `d` decided, after
  // the vertex's light samples brought `direct` into L through `shadowRays`
  // rays (both 0 if they are not split): the other estimates are traced at
  // once, into L; false if this line ends here.
  bool split(PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c,
             const SplitDecision& d, const Color& direct, uint64_t shadowRays, uint64_t& rays, Color& L,
             PathObserver* observer, Continuation* pending, int& pendingCount) const;
  void traceBranches(int n, float u, float key, const PathState& first, const SurfaceInteraction& si, const BSDF& bsdf,
                     uint32_t slots, size_t slot, const PathContext& c, uint64_t& rays, Color& L,
                     PathObserver* observer) const;
  // mnee (manifold_nee.cpp): the manifold connection from `si` as a shadow
  // request (false if there is none), and the chain count after scattering.
  bool manifoldLightSample(const PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c,
                           uint32_t slot, ShadowRequest& out) const;
  int manifoldChainAfter(int chain, const BSDF& bsdf, bool refracted, bool reflected) const;
  void prepareSmsCasters(const Scene& scene);
  // sms: a chain from a random seed on the casters; the solver's settings.
  std::optional<ManifoldConnection> smsTrial(const Scene& scene, const SurfaceInteraction& si, const Vec3& y,
                                             Pcg32& rng) const;
  const Light* chooseLight(const Scene& scene, const Vec3& p, float u, float* pmf) const;
  float lightPmf(const Scene& scene, const Vec3& p, const Light* light) const;

  PathTracerSettings settings_;
  LightSampler ownLights_;                                     // light_selection uniform | power
  std::vector<int> smsCasters_;                                // sms: the shapes seeds are drawn on …
  DiscreteDistribution smsCasterAreas_;                        // … by area
  std::shared_ptr<const SpatialLightSampler> spatial_;         // light_selection spatial
};

}  // namespace lb
