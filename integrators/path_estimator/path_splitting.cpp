// The path estimator's learned Russian roulette and splitting (`rrs: adrrs |
// ears`; the rules and their sources are in roulette_splitting.h). At a vertex
// the reflected radiance's estimate (the vertex's light samples, then the
// BSDF-sampled direction and all that follows) is taken n = ⌊q + u⌋ times,
// each with throughput β/q: E[n/q] = 1 for any q > 0, so the estimator stays
// unbiased whatever the cache has learned. The light samples are split with
// the continuation, as the authors' code does (iRath96/ears,
// recursive_path.cpp): where direct light is most of a pixel's variance (the
// plates of Veach's scene), splitting only the continuation cannot reach it.
// With rrs_split_light false they are taken once, before, and only the
// continuation is split (where light sampling is nearly noiseless, as under
// the Cornell box's large light, that spends nothing on it).
#include <cassert>
#include <cstring>
#include <optional>
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

namespace {
uint64_t bitsOf(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
// `c` with another sampler (a split continuation's own); all else, the
// rough twins of regularize included, as the line's.
PathContext withSampler(const PathContext& c, Sampler& sampler) {
  return {c.scene, sampler, c.maxDepth, c.firstEmission, c.entryDimension, c.guide, c.varianceAware, c.rrs,
          c.regularization};
}
}  // namespace

std::optional<float> PathEstimator::splitFactor(const PathState& s, size_t slot, const BSDF& bsdf,
                                                const RrsView& r) const {
  // EARS decides from the first hit on, ADRRS from the second vertex (the
  // depths iRath96/ears recommends for each); before, neither roulette nor
  // splitting, as there.
  const int firstVertex = r.method == RrsMethod::Ears ? 0 : 1;
  if (r.learned && s.vertex < firstVertex) return 1.f;
  // Classic roulette (none here): the warm-up's rule, and where the cache
  // knows nothing or the vertex is specular.
  if (!r.learned || bsdf.isDelta()) return std::nullopt;
  const ContinuationStats* stats = r.cache->lookup(slot);
  if (!stats) return std::nullopt;
  Color w = s.beta * r.relativeScale;  // the throughput relative to the pixel
  if (r.method == RrsMethod::Adrrs) return clampSplitFactor(adrrsFactor(w, stats->mean));
  // EARS without a cost or an image error has no factor to give.
  if (!(stats->cost > 0) || !(r.imageFactor > 0)) return std::nullopt;
  return clampSplitFactor(earsFactor(w, *stats, r.imageFactor));
}

PathEstimator::SplitDecision PathEstimator::decideSplit(const PathState& s, const SurfaceInteraction& si,
                                                        const BSDF& bsdf, const PathContext& c) const {
  SplitDecision d;
  d.slot = c.rrs->cache->slot(si.p, s.ray.d);
  std::optional<float> factor = splitFactor(s, d.slot, bsdf, *c.rrs);
  if (!factor) return d;  // classic roulette
  d.learned = true;
  d.q = *factor;
  // Caps that keep a wrong cache from multiplying paths without end; any
  // q > 0 is unbiased, so capping it is too.
  if (d.q > 1) d.q = s.nesting >= MaxNesting ? 1.f : std::min(d.q, std::max(1.f, MaxSplitProduct / s.splitProduct));
  // q = 1 keeps the one path whatever u is: drawn only where it matters
  // (the slots are fixed, so skipping one changes no other number).
  if (d.q != 1) {
    c.sampler.setDimension(vertexBase(s, c) + settings_.scatterSlot() + 3);
    d.u = c.sampler.get1D();
    d.n = int(d.q + d.u);  // ⌊q + u⌋: E[n] = q
  }
  assert(d.n < MaxSplitContinuations);
  return d;
}

// Continuations 1 … n − 1 of a split (n > 1), each drawing from a sampler
// of its own (keyed by the vertex's two draws and its point, so two vertices
// share a stream only if all five agree): its light samples, traced at once,
// and its direction. All directions are drawn first, while a guide (guided)
// still holds this vertex's distribution: tracing a continuation prepares it
// at the vertices further on. (Apart from split() so that its arrays are
// built only where a path splits.)
void PathEstimator::traceBranches(int n, float u, float key, const PathState& first, const SurfaceInteraction& si,
                                  const BSDF& bsdf, uint32_t slots, size_t slot, const PathContext& c, uint64_t& rays,
                                  Color& L, PathObserver* observer) const {
  std::optional<IndependentSampler> own[MaxSplitContinuations];
  PathState next[MaxSplitContinuations];
  bool alive[MaxSplitContinuations];
  Color direct[MaxSplitContinuations];
  uint64_t shadowRays[MaxSplitContinuations];
  ShadowRequest shadows[MaxShadowRequests];
  const bool guided = c.guide && c.guide->active();
  for (int b = 1; b < n; ++b) {
    own[b].emplace(c.sampler.seed());
    own[b]->start(hashValues(bitsOf(u), bitsOf(key), bitsOf(si.p.x), bitsOf(si.p.y), bitsOf(si.p.z)), uint64_t(b));
    next[b] = first;
    ++next[b].nesting;
    PathContext branch = withSampler(c, *own[b]);
    const uint64_t raysBefore = rays;
    direct[b] = Color(0.f);
    const int m = settings_.rrsSplitLight ? lightSamples(next[b], si, bsdf, branch, guided, shadows) : 0;
    for (int i = 0; i < m; ++i) {
      if (!shadows[i].tested) {
        ++rays;
        if (c.scene.occluded(shadows[i].ray)) continue;
      }
      direct[b] += shadows[i].contribution;
    }
    shadowRays[b] = rays - raysBefore;
    if (observer && !isBlack(direct[b])) observer->splitLight(direct[b]);
    alive[b] = scatter(next[b], si, bsdf, *own[b], slots, c.guide, false);
  }
  for (int b = 1; b < n; ++b) {
    PathContext branch = withSampler(c, *own[b]);
    const uint64_t raysBefore = rays;
    Color Lb = direct[b];
    if (alive[b]) {
      if (observer) observer->scattered(si, next[b]);
      ++next[b].vertex;
      Lb += trace(next[b], branch, rays, observer);
    }
    L += Lb;
    c.rrs->record(slot, perUnitThroughput(Lb, first.beta), double(rays - raysBefore + shadowRays[b]));
  }
}

bool PathEstimator::split(PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c,
                          const SplitDecision& d, const Color& direct, uint64_t shadowRays, uint64_t& rays, Color& L,
                          PathObserver* observer, Continuation* pending, int& pendingCount) const {
  const uint32_t slots = vertexBase(s, c);
  const size_t slot = d.slot;
  if (!d.learned) {
    // Classic roulette, exactly as rrs: classic (path_length.h, on β after
    // the direction; the light samples taken in full). What it teaches the
    // cache is recorded as a learned q = p would be: only a continuation it
    // keeps, per unit of the β/p it carries, plus the light samples per unit
    // of β. (Recording a killed one as a zero kept the mean but inflated the
    // cell's second moment by 1/p and cut its cost by p, so EARS's q came out
    // 1/p too large at every cell classic roulette had taught; iRath96/ears
    // records only the continuations taken. Issue 37.)
    const Color beta = s.beta;
    const Color directPerUnit = perUnitThroughput(direct, beta);
    if (!scatter(s, si, bsdf, c.sampler, slots, c.guide, false)) {
      // A continuation taken that found nothing.
      if (pendingCount < MaxRecordedVertices)
        pending[pendingCount++] = {slot, beta, L, directPerUnit, rays - shadowRays};
      return false;
    }
    float p = 1;
    if (!survivesRoulette(s, c.sampler, slots, &p)) return false;
    if (pendingCount < MaxRecordedVertices)
      pending[pendingCount++] = {slot, beta / p, L, directPerUnit, rays - shadowRays};
    return true;
  }
  // Continuation 0 goes on in the caller's loop, with the caller's sampler
  // (its light samples, scaled by 1/q, are already in L): its direction
  // first (slots in order), then the split's key.
  PathState first = s;
  first.beta /= d.q;
  first.splitProduct *= d.q;
  s = first;
  if (d.n == 0) return false;
  const bool scattered = scatter(s, si, bsdf, c.sampler, slots, c.guide, false);
  if (d.n > 1) {
    c.sampler.setDimension(slots + settings_.scatterSlot() + 4);
    traceBranches(d.n, d.u, c.sampler.get1D(), first, si, bsdf, slots, slot, c, rays, L, observer);
  }
  // What continuation 0 brings back: its light samples, then what the line
  // adds from here on (after the other continuations' L).
  if (pendingCount < MaxRecordedVertices)
    pending[pendingCount++] = {slot, first.beta, L, perUnitThroughput(direct, first.beta), rays - shadowRays};
  return scattered;
}

}  // namespace lb
