#pragma once
// Unidirectional path tracing with the switches of the classic comparisons
// (Veach 1997 ch. 9; pbrt-v4 §13.4):
//
//   sampling   bsdf | cosine | uniform   how non-delta bounces choose directions
//   nee        true | false              next-event estimation (one light sample per vertex)
//   mis        power | balance | none    how NEE and emitter hits are combined
//   max_depth, rr, rr_depth              path length and roulette (path_length.h)
//
// With nee on and mis none, emitters hit after a non-delta bounce are ignored
// (pure NEE); with nee off, only hits count, so delta lights are invisible.
#include "core/params.h"
#include "integrators/path_length.h"
#include "integrators/integrator.h"

namespace lb {

enum class DirectionSampling { Bsdf, Cosine, Uniform };
enum class MisHeuristic { None, Balance, Power };

struct PathTracerSettings {
  DirectionSampling sampling = DirectionSampling::Bsdf;
  bool nee = true;
  MisHeuristic mis = MisHeuristic::Power;
  PathLength length;

  static PathTracerSettings read(Params& p);
};

class PathTracer final : public PixelIntegrator {
 public:
  explicit PathTracer(PathTracerSettings s) : settings_(s) {}

  // Radiance arriving along `ray` over paths of at most `maxSegments`
  // segments. Without `firstEmission`, the emission of the first surface hit
  // (or of the environment, if the ray escapes) is left out: the caller counts
  // that light itself (the irradiance cache's records gather only indirect
  // light). `firstHitDistance`, if given, receives the first hit's distance
  // (infinity if the ray escapes).
  Color incidentRadiance(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays, int maxSegments,
                         bool firstEmission, float* firstHitDistance = nullptr) const;

 protected:
  Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override;

 private:
  float misWeight(float pdfThis, float pdfOther) const;
  PathTracerSettings settings_;
};

}  // namespace lb
