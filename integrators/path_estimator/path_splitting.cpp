// The path estimator's learned Russian roulette and splitting (`rrs: adrrs |
// ears`; the rules and their sources are in roulette_splitting.h). At a vertex
// the continuation (the BSDF-sampled direction and all that follows) is
// taken n = ⌊q + u⌋ times, each with throughput β/q: E[n/q] = 1 for any q > 0,
// so the estimator stays unbiased whatever the cache has learned.
#include <cstring>
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

namespace {
uint64_t bitsOf(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
}  // namespace

float PathEstimator::splitFactor(const PathState& s, size_t slot, const BSDF& bsdf, const RrsView& r) const {
  const PathLength& length = settings_.length;
  const int segments = s.vertex + 1;
  // Classic roulette on the throughput (as path_length.h, on β before the
  // direction is drawn): the warm-up's rule, and the fallback where the
  // cache knows nothing or the vertex is specular.
  float classic = length.russianRoulette && segments >= length.rrDepth
                      ? std::min(1.f, maxComponent(s.beta) * s.etaScale)
                      : 1.f;
  // EARS decides from the first hit on, ADRRS from the second vertex (the
  // depths iRath96/ears recommends for each).
  const int firstVertex = r.method == RrsMethod::Ears ? 0 : 1;
  if (r.learned && s.vertex < firstVertex) return 1.f;
  if (!r.learned || bsdf.isDelta()) return classic;
  const ContinuationStats* stats = r.cache->lookup(slot);
  if (!stats) return classic;
  Color w = s.beta * r.relativeScale;  // the throughput relative to the pixel
  float q = r.method == RrsMethod::Adrrs ? adrrsFactor(w, stats->mean) : earsFactor(w, *stats, r.imageFactor);
  return clampSplitFactor(q);
}

bool PathEstimator::split(PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c,
                          uint64_t& rays, Color& L, PathObserver* observer, Continuation* pending,
                          int& pendingCount) const {
  const RrsView& r = *c.rrs;
  const uint32_t slots = vertexBase(s, c);
  const size_t slot = r.cache->slot(si.p, s.ray.d);
  float q = splitFactor(s, slot, bsdf, r);
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
  // Continuations 1 … n − 1, each drawing from a sampler of its own (keyed
  // by this vertex's two draws), traced now.
  for (int b = 1; b < n; ++b) {
    IndependentSampler own(c.sampler.seed());
    own.start(hashValues(bitsOf(u), bitsOf(key), uint64_t(s.vertex)), uint64_t(b));
    PathContext branch{c.scene, own, c.maxDepth, c.firstEmission, c.entryDimension, c.guide, c.varianceAware, c.rrs};
    PathState next = first;
    ++next.nesting;
    const uint64_t raysBefore = rays;
    Color Lb(0.f);
    if (scatter(next, si, bsdf, own, slots, c.guide, false)) {
      if (observer) observer->scattered(si, next);
      ++next.vertex;
      Lb = trace(next, branch, rays, observer);
    }
    L += Lb;
    r.record(slot, perUnitThroughput(Lb, first.beta), double(rays - raysBefore));
  }
  if (n == 0) return false;
  if (pendingCount < MaxRecordedVertices) pending[pendingCount++] = {slot, first.beta, L, rays};
  return scattered;
}

}  // namespace lb
