#pragma once
// Path length and Russian roulette, read once with the same keys and meaning
// for every integrator that traces paths, so their images estimate the same
// sum over path lengths:
//   max_depth  32    maximum path length in SEGMENTS (the camera ray is 1,
//                    direct light is 2); -1 = unlimited (requires rr; BDPT
//                    caps it at 4096 segments, the size of its subpath arrays)
//
// The path-length rule, the same for all six integrators: max_depth bounds
// the TOTAL number of segments from the camera to the light, however the
// path was built. A path joined from a camera part of j segments and a light
// part of k segments counts j + k (plus one for a connecting segment, as in
// BDPT and NEE): a photon stored after k segments from the light (photon
// mapping, SPPM, the irradiance cache's photon base) may only be used at a
// camera vertex reached after j segments if j + k <= max_depth, a final-gather
// or record ray adds its own segments to j, and an irradiance record computed
// for the segments left after j is only reused at that same j. So at equal
// max_depth every integrator estimates the same truncated integral; 0 renders
// black and 1 shows only the emitters seen directly.
//   rr         true  Russian roulette on the path throughput
//   rr_depth   3     segments before roulette may start
#include "core/params.h"
#include "core/sampler.h"

namespace lb {

struct PathLength {
  int maxDepth = 32;
  bool russianRoulette = true;
  int rrDepth = 3;

  int maxSegments() const { return maxDepth < 0 ? 1 << 20 : maxDepth; }

  // The probability survivesRoulette() keeps a path with (1 where it does not play).
  float survivalProbability(int segments, const Color& beta, float etaScale) const {
    if (!russianRoulette || segments < rrDepth) return 1.f;
    return std::min(1.f, maxComponent(beta) * etaScale);
  }
  // Russian roulette after `segments` segments (pbrt-v4 §13.4): survive with
  // probability min(1, max β·η²) and reweight β; false if the path ends.
  // etaScale removes radiance's 1/η² scaling from the decision.
  bool survivesRoulette(int segments, Color& beta, float etaScale, Sampler& sampler) const {
    float survive = survivalProbability(segments, beta, etaScale);
    if (survive >= 1) return true;
    if (sampler.get1D() >= survive) return false;
    beta /= survive;
    return true;
  }

  static PathLength read(Params& p) {
    PathLength s;
    s.maxDepth = p.getInt("max_depth", 32,
                          {"longest path in segments, camera to light (the camera ray is 1, direct light 2); -1: unlimited",
                           Range::atLeast(-1)});
    s.russianRoulette = p.getBool("rr", true, "Russian roulette on the path throughput (pbrt-v4 13.4)");
    s.rrDepth = p.getInt("rr_depth", 3, {"segments before Russian roulette may end a path", Range::atLeast(1)});
    if (s.maxDepth == -1 && !s.russianRoulette) p.fail("max_depth", "unlimited depth needs rr: true to terminate");
    // Without roulette a path in a closed white box runs to max_depth: 2^31 - 1
    // ran silently for ever (issue 34). 4096, the bidirectional buffers' size.
    if (s.maxDepth > 4096 && !s.russianRoulette)
      p.fail("max_depth", "without rr a path runs to max_depth: at most 4096, or rr: true");
    return s;
  }
};

}  // namespace lb
