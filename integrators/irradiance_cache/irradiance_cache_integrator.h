#pragma once
// Irradiance caching (Ward, Rubinstein, Clear 1988) with gradients (Ward &
// Heckbert 1992). Each camera sample follows delta and glossy bounces as the
// path tracer does (NEE + MIS, Russian roulette) to the first diffuse surface
// x, and there adds
//   direct light     one NEE sample (no MIS: no BSDF-sampled ray leaves x)
//   caustics         base photon only: the caustic map at x
//   indirect light   f · E(x), E interpolated from the cache's records, or a
//                    new record computed at x when none is valid there.
// Only purely diffuse surfaces are cached; a record's incident radiance comes
// from the path tracer (base: path) or from the global photon map after the
// first bounce (base: photon — the cache then replaces photon mapping's
// final gather).
//
//   a                  0.15     Ward's error threshold: records reach a·R
//   spacing            pixels   units of min/max_spacing: pixels | world
//   min_spacing        2        smallest reach a·R of a record
//   max_spacing        64       largest reach a·R of a record
//   theta_strata       16       M: hemisphere strata in sin²θ
//   phi_strata         48       N: hemisphere strata in azimuth (M·N rays per record)
//   gradients          true     extrapolate with Ward & Heckbert's gradients
//   neighbour_clamping true     Křivánek et al. 2006
//   prepass_levels     3        low-resolution passes before the render, at
//                               pixel strides 2^levels … 2 (0: none)
//   base               path     path | photon
//   record_image       true     write <output>_records.png: records over the render
//   max_depth, rr, rr_depth     as for the path tracer (path_length.h); a record
//                               computed for the segments left after a camera
//                               path of j segments serves only lookups at that j
//   base photon only:  global_photons (200000), caustic_photons (200000),
//                      k (30), max_radius (0: 5% of the scene's radius)
//
// Biased but consistent in a → 0 with growing strata: interpolation blurs
// irradiance between records, and each record's noise is frozen into a
// smooth blotch instead of averaging out over passes.
#include <optional>
#include "core/params.h"
#include "integrators/integrator.h"
#include "integrators/irradiance_cache/irradiance_cache.h"
#include "integrators/path_estimator/path_estimator.h"
#include "integrators/path_length.h"
#include "integrators/photon_map/photon_map_settings.h"

namespace lb {

enum class CacheBase { Path, Photon };

struct IrradianceCacheSettings {
  CacheSettings cache;
  HemisphereStrata strata;
  int prepassLevels = 3;
  CacheBase base = CacheBase::Path;
  bool recordImage = true;
  PathLength length;
  PhotonMapSettings photonMaps;  // base photon
  static IrradianceCacheSettings read(Params& p);
};

struct IrradianceCacheStats {
  size_t prepassRecords = 0;
  double prepassSeconds = 0;
  uint64_t lookups = 0, hits = 0;
  double lookupSeconds = 0, recordSeconds = 0;  // summed over threads
  uint64_t nonFiniteIncident = 0;               // hemisphere samples dropped as NaN/Inf
};

class IrradianceCacheIntegrator final : public Integrator {
 public:
  std::string splitRefusal() const override {
    return "its cache is built from the render's own earlier passes; each chunk would start an empty cache";
  }
  explicit IrradianceCacheIntegrator(IrradianceCacheSettings s);
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::vector<std::string> writeExtraOutputs(const std::string& stem) const override;
  std::vector<std::string> extraOutputPaths(const std::string& stem) const override {
    return settings_.recordImage ? std::vector<std::string>{stem + "_records.png"} : std::vector<std::string>{};
  }
  bool replaysSamples() const override { return true; }
  std::optional<Color> replaySample(const Scene& scene, const Sampler& prototype, int x, int y, uint64_t sample) override;

  const IrradianceCache& cache() const { return *cache_; }
  const IrradianceCacheStats& stats() const { return stats_; }
  // A record computed at a diffuse surface point, its normal turned towards
  // si.wo (exposed for tests and benchmarks). `key` seeds its random numbers.
  // The base estimator: indirect radiance arriving along a ray leaving a
  // surface (emission of the first surface hit excluded), and the hit distance.
  IncidentSample incident(const Ray& ray, Sampler& sampler, int segmentsLeft, uint64_t& rays) const;
  IrradianceRecord computeRecordAt(const SurfaceInteraction& si, uint64_t key, int segmentsLeft, uint64_t& rays,
                                   uint64_t* droppedSamples = nullptr) const;

 private:
  Color Li(const Ray& ray, Sampler& sampler, uint64_t key, LocalRecords& local, uint64_t& rays) const;
  Color irradiance(const SurfaceInteraction& si, const Vec3& n, uint64_t key, int segmentsLeft, LocalRecords& local,
                   uint64_t& rays) const;
  IncidentSample photonIncident(const Ray& ray, Sampler& sampler, int segmentsLeft, uint64_t& rays) const;
  void runPass(const Film* film, int stride, uint64_t sampleIndex, const Sampler& prototype, PassStats& stats,
               const std::function<void(int x, int y, const Color&)>& result);

  IrradianceCacheSettings settings_;
  PathEstimator base_;
  const Scene* scene_ = nullptr;
  const Film* film_ = nullptr;
  uint64_t seed_ = 0;
  float pixelAngle_ = 0;  // radians per pixel at the image centre
  std::unique_ptr<IrradianceCache> cache_;
  PhotonMap global_, caustic_;
  DensityQuery query_;
  IrradianceCacheStats stats_;
};

}  // namespace lb
