// The path estimator's learned Russian roulette and splitting (`rrs: adrrs |
// ears`; the rules and their sources are in roulette_splitting.h). At a vertex
// the continuation (the BSDF-sampled direction and all that follows) is
// taken n = ⌊q + u⌋ times, each with throughput β/q: E[n/q] = 1 for any q > 0,
// so the estimator stays unbiased whatever the cache has learned.
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

bool PathEstimator::split(PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c,
                          uint64_t& rays, Color& L, PathObserver* observer, Continuation* pending,
                          int& pendingCount) const {
  const RrsView& r = *c.rrs;
  const uint32_t slots = vertexBase(s, c);
  const size_t slot = r.cache->slot(si.p, s.ray.d);
  std::optional<float> factor = splitFactor(s, slot, bsdf, r);
  if (!factor) {
    // Classic roulette, exactly as rrs: classic (path_length.h, on β after
    // the direction). Its continuation is recorded as a learned q = p would
    // be (below): only if taken, per unit of the throughput β/p it carries.
    // (Recording a killed one as a zero and a survivor per unit of β, as
    // before, kept the mean but inflated the cell's second moment by 1/p
    // and cut its cost by p, so EARS's q came out 1/p too large at every
    // cell classic roulette had taught; iRath96/ears records only the
    // continuations taken. Issue 37.)
    const Color beta = s.beta;
    if (!scatter(s, si, bsdf, c.sampler, slots, c.guide, false)) {
      // A continuation taken that found nothing.
      if (pendingCount < MaxRecordedVertices) pending[pendingCount++] = {slot, beta, L, rays};
      return false;
    }
    float p = 1;
    if (!survivesRoulette(s, c.sampler, slots, &p)) return false;
    if (pendingCount < MaxRecordedVertices) pending[pendingCount++] = {slot, beta / p, L, rays};
    return true;
  }
  float q = *factor;
  // Caps that keep a wrong cache from multiplying paths without end; any
  // q > 0 is unbiased, so capping it is too.
  if (q > 1) q = s.nesting >= MaxNesting ? 1.f : std::min(q, std::max(1.f, MaxSplitProduct / s.splitProduct));
  // Continuation 0 goes on in the caller's loop, with the caller's sampler:
  // its direction first (slots in order), then the split's two numbers.
  PathState first = s;
  first.beta /= q;
  first.splitProduct *= q;
  s = first;
  const bool scattered = scatter(s, si, bsdf, c.sampler, slots, c.guide, false);
  c.sampler.setDimension(slots + settings_.scatterSlot() + 3);
  float u = c.sampler.get1D();
  float key = c.sampler.get1D();
  const int n = int(q + u);  // ⌊q + u⌋: E[n] = q
  assert(n < MaxSplitContinuations);
  // Continuations 1 … n − 1, each drawing from a sampler of its own (keyed
  // by this vertex's two draws and its point, so two vertices share a
  // stream only if all five agree). All their directions are drawn first,
  // while a guide (guided) still holds this vertex's distribution: tracing
  // a continuation prepares it at the vertices further on.
  std::optional<IndependentSampler> own[MaxSplitContinuations];
  PathState next[MaxSplitContinuations];
  bool alive[MaxSplitContinuations];
  for (int b = 1; b < n; ++b) {
    own[b].emplace(c.sampler.seed());
    own[b]->start(hashValues(bitsOf(u), bitsOf(key), bitsOf(si.p.x), bitsOf(si.p.y), bitsOf(si.p.z)), uint64_t(b));
    next[b] = first;
    ++next[b].nesting;
    alive[b] = scatter(next[b], si, bsdf, *own[b], slots, c.guide, false);
  }
  for (int b = 1; b < n; ++b) {
    PathContext branch{c.scene, *own[b], c.maxDepth, c.firstEmission, c.entryDimension, c.guide, c.varianceAware, c.rrs};
    const uint64_t raysBefore = rays;
    Color Lb(0.f);
    if (alive[b]) {
      if (observer) observer->scattered(si, next[b]);
      ++next[b].vertex;
      Lb = trace(next[b], branch, rays, observer);
    }
    L += Lb;
    r.record(slot, perUnitThroughput(Lb, first.beta), double(rays - raysBefore));
  }
  if (n == 0) return false;
  if (pendingCount < MaxRecordedVertices) pending[pendingCount++] = {slot, first.beta, L, rays};
  return scattered;
}

}  // namespace lb
