#pragma once
// Path length and Russian roulette, read once with the same keys and meaning
// for every integrator that traces paths, so their images estimate the same
// sum over path lengths:
//   max_depth  32    maximum path length in SEGMENTS (the camera ray is 1,
//                    direct light is 2); -1 = unlimited (requires rr; BDPT
//                    caps it at 4096 segments, the size of its subpath arrays)
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

  // Russian roulette after `segments` segments (pbrt-v4 §13.4): survive with
  // probability min(1, max β·η²) and reweight β; false if the path ends.
  // etaScale removes radiance's 1/η² scaling from the decision.
  bool survivesRoulette(int segments, Color& beta, float etaScale, Sampler& sampler) const {
    if (!russianRoulette || segments < rrDepth) return true;
    float survive = std::min(1.f, maxComponent(beta) * etaScale);
    if (survive >= 1) return true;
    if (sampler.get1D() >= survive) return false;
    beta /= survive;
    return true;
  }

  static PathLength read(Params& p) {
    PathLength s;
    s.maxDepth = p.getInt("max_depth", 32);
    if (s.maxDepth < -1) p.fail("max_depth", "must be >= 0, or -1 for unlimited");
    s.russianRoulette = p.getBool("rr", true);
    s.rrDepth = p.getInt("rr_depth", 3);
    if (s.rrDepth < 1) p.fail("rr_depth", "must be at least 1");
    if (s.maxDepth == -1 && !s.russianRoulette) p.fail("max_depth", "unlimited depth needs rr: true to terminate");
    return s;
  }
};

}  // namespace lb
