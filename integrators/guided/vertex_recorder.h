#pragma once
// Records each scattering vertex of a camera path for the guided integrator's
// learning (a PathObserver, path_estimator.h): the radiance the rest of the
// path brings back to it (each later contribution divided by the vertex's
// throughput), and what its direction reached (the emission there and the
// learned value of scattering on, for Q-learning).
//
// A path may branch (rrs: adrrs | ears splits a continuation into several,
// path_splitting.cpp), so "the rest of the path" is the vertex's own
// subtree, not everything reported after it. The recorder keeps the chain of
// the current line's recorded ancestors: a contribution goes to those only,
// and a new scattering event first drops the records that are not its
// ancestors — those of a deeper nesting (a finished branch), and those of
// its own nesting at its vertex or later (a finished sibling). The
// estimator reports the branches traced at once before the continuation its
// line goes on with, each depth first (PathObserver), which this rule reads.
// Without branches the chain is every record of the path, in order.
#include <vector>
#include "integrators/guided/guiding_method.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb::guiding {

class VertexRecorder final : public PathObserver {
 public:
  VertexRecorder(std::vector<GuideVertex>& records, const GuidingMethod& method)
      : records_(records), method_(method) {}

  void shaded(const SurfaceInteraction& si, const BSDF* bsdf, const Color& emitted, const Color& added) override {
    // `emitted`, divided by the previous vertex's throughput, is the emission
    // its direction found, less what NEE already found (so Q-learning does
    // not learn to aim at lights NEE reaches).
    if (lastRecorded_ && !chain_.empty()) {
      GuideVertex& prev = records_[chain_.back().record];
      prev.emitted = luminance(emitted / glm::max(prev.beta, Color(1e-30f)));
      if (bsdf) prev.scattered = method_.scatteredValue(si, *bsdf);
    }
    credit(added);
  }

  // Before the split's continuations are traced, the chain is still the
  // ancestors of the vertex whose light samples these are.
  void splitLight(const Color& added) override { credit(added); }

  void scattered(const SurfaceInteraction& si, const PathState& s) override {
    while (!chain_.empty() && (chain_.back().nesting > s.nesting ||
                               (chain_.back().nesting == s.nesting && chain_.back().vertex >= s.vertex)))
      chain_.pop_back();
    lastRecorded_ = !s.prevDelta;
    if (!lastRecorded_) return;
    chain_.push_back({records_.size(), s.nesting, s.vertex});
    records_.push_back({si.p, orientationClass(si), s.ray.d, s.prevPdf, s.beta});
  }

 private:
  // `added` to every record of the chain (each per unit of its throughput).
  void credit(const Color& added) {
    if (isBlack(added)) return;
    for (const Link& link : chain_) {
      GuideVertex& r = records_[link.record];
      for (int ch = 0; ch < 3; ++ch)
        if (r.beta[ch] > 0) r.incident[ch] += added[ch] / r.beta[ch];
    }
  }
  struct Link {
    size_t record;  // index into records_
    int nesting, vertex;
  };
  std::vector<GuideVertex>& records_;
  const GuidingMethod& method_;
  std::vector<Link> chain_;   // the current line's recorded ancestors, root first
  bool lastRecorded_ = false;  // whether the previous vertex has a record to close
};

}  // namespace lb::guiding
