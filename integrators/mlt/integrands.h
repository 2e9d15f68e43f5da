#pragma once
// What the Metropolis chains of `mlt` integrate (metropolis.h): three maps
// from a primary sample vector to contributions, all normalised so that a
// pixel's value is P · E_u[contributions in it] for u uniform (P pixels).
//
//  PathIntegrand         pssmlt, base: path. One stream: the raster position
//                        (2 numbers, u·(width, height)) and then the path
//                        estimator's own layout (path_estimator.h).
//  BdptIntegrand         pssmlt, base: bdpt. Streams camera, light,
//                        connection; every (s, t) strategy of one BDPT sample,
//                        MIS-weighted (Veach 1997 ch. 10), each at its own
//                        raster position (t = 1 splats anywhere).
//  MultiplexedIntegrand  mmlt (Hachisuka, Kaplanyan, Dachsbacher 2014): a
//                        fourth stream, the control, picks the path length
//                        k ∈ [1, K] (K = max_depth) with probability p(k)
//                        (uniform, or set from a pilot: see mlt.h,
//                        length_selection) and one strategy (s, t) with
//                        s + t − 1 = k uniformly; only that strategy's
//                        subpaths are built (t camera and s light vertices)
//                        and its contribution is  w_{s,t} · C_{s,t} / p(k, s),
//                        the MIS-weighted contribution over the selection
//                        probability (their Eq. 6-8). For k = 1 the only
//                        strategy is s = 0 (BDPT covers (1,1) by (0,2)).
//                        The chain's target is therefore proportional to
//                        one weighted strategy at a time, so it spends its
//                        mutations on the strategies that carry the light.
#include "integrators/bidirectional/all_strategies.h"
#include "integrators/mlt/metropolis.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb::mlt {

class PathIntegrand final : public PrimarySpaceIntegrand {
 public:
  PathIntegrand(const Scene& scene, const PathEstimator& estimator) : scene_(scene), estimator_(estimator) {}
  int streams() const override { return 1; }
  void evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const override;

 private:
  const Scene& scene_;
  const PathEstimator& estimator_;
};

class BdptIntegrand final : public PrimarySpaceIntegrand {
 public:
  BdptIntegrand(const Scene& scene, PathLength length, bidir::MisWeighting mis)
      : scene_(scene), length_(length), mis_(mis) {}
  int streams() const override { return 3; }
  void evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const override;

 private:
  const Scene& scene_;
  PathLength length_;
  bidir::MisWeighting mis_;
};

class MultiplexedIntegrand final : public PrimarySpaceIntegrand {
 public:
  enum Stream { Control = 0, Camera = 1, Light = 2, Connection = 3 };
  // Lengths are chosen uniformly until setLengthProbabilities().
  MultiplexedIntegrand(const Scene& scene, int maxSegments, bidir::MisWeighting mis);
  // p(k) for k = 1 … K (index k − 1); normalised here. Every p(k) must be
  // positive, or paths of that length would be lost.
  void setLengthProbabilities(const std::vector<double>& p);
  const std::vector<float>& lengthProbabilities() const { return lengthPmf_; }
  int streams() const override { return 4; }
  void evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const override;

  // The strategies of length k (segments): s = 0 … k, without (1, 1).
  static int strategies(int k) { return k == 1 ? 1 : k + 1; }
  struct Choice {
    int k, s, t;
    float probability;
  };
  // Length and strategy from the control stream's first two numbers.
  Choice choose(float uLength, float uStrategy) const;

 private:
  const Scene& scene_;
  int maxSegments_;
  std::vector<float> lengthPmf_, lengthCdf_;  // K entries; the CDF ends at 1
  bidir::MisWeighting mis_;
};

// A pilot for the length probabilities (mlt.h, length_selection: pilot): the
// mean target value of each length over n uniform vectors, by length k − 1.
// Deterministic for a seed whatever the thread count.
std::vector<double> lengthContributions(const MultiplexedIntegrand& integrand, const SmallStep& step, uint64_t seed,
                                        uint64_t n, uint64_t& rays);

}  // namespace lb::mlt
