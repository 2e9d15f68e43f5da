#pragma once
// Photon mapping (Jensen 1996; "Realistic Image Synthesis Using Photon
// Mapping", 2001). Preprocess traces two photon maps; each camera sample then
// follows specular bounces to the first non-specular surface x and adds
//   direct light     next-event estimation (MIS with the gather rays where
//                    the BSDF is glossy: those reaching an emitter or
//                    escaping to the environment add its weighted radiance)
//   caustics         the caustic map (L S+ D photons) at x
//   indirect light   final gathering: `final_gather` BSDF-sampled rays, each
//                    looking up the global map where it lands (through
//                    specular surfaces to the first non-specular one);
//                    final_gather: 0 shows the global map directly at x instead
//
//   global_photons   200000  photon paths emitted for the global map
//   caustic_photons  200000  photon paths emitted for the caustic map
//   k                30      photons per density estimate (at least 2: the k-th sets the radius;
//                            0: every photon within max_radius, a fixed-radius estimate)
//   max_radius       0       largest gather radius (world units); 0 = 5% of the scene's radius
//   filter           cone    cone | epanechnikov | box
//   final_gather     8       gather rays per camera sample (0: visualise the global map)
//   max_depth        32      total path length in segments, camera to light (path_length.h)
//   density_images   false   also write each map's photon density (irradiance) image
//   stats            false   print map statistics (photons stored, memory, build time)
//
// Biased but consistent: the density estimates blur light over the gather
// disc (see photon_map.h), and the bias vanishes as photons grow and radii
// shrink.
#include "core/params.h"
#include "integrators/integrator.h"
#include "integrators/photon/photon_map.h"

namespace lb {

// The photon maps' keys, shared with the irradiance cache's photon records:
// global_photons, caustic_photons, k, max_radius.
struct PhotonMapSettings {
  size_t globalPhotons = 200000, causticPhotons = 200000;
  DensityQuery query;
  float maxRadius = 0;  // 0: automatic, 5% of the scene's bounding radius
  std::string file, key;  // where global_photons was given, for the memory check's message
  int line = 0;
  static PhotonMapSettings read(Params& p);
  DensityQuery queryFor(const Scene& scene) const;
  // Refuses (ConfigError naming global_photons) maps that would not fit in the
  // memory available: a pilot of 4096 photon paths measures photons stored
  // per path on this scene, extrapolated to the requested counts.
  void checkMemory(const Scene& scene, uint64_t seed, int maxBounces) const;
};

struct PhotonSettings : PhotonMapSettings {
  int finalGather = 8;
  int maxDepth = 32;
  bool densityImages = false, stats = false;
  static PhotonSettings read(Params& p);
};

class PhotonMapper final : public PixelIntegrator {
 public:
  explicit PhotonMapper(PhotonSettings s) : settings_(s) {}
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  std::vector<std::string> writeExtraOutputs(const std::string& stem) const override;
  const PhotonMap& globalMap() const { return global_; }
  const PhotonMap& causticMap() const { return caustic_; }

 protected:
  Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override;

 private:
  Color gather(const Scene& scene, const SurfaceInteraction& x, int segmentsLeft, Sampler& sampler, uint64_t& rays,
               std::vector<std::pair<size_t, float>>& scratch) const;
  PhotonSettings settings_;
  DensityQuery query_;
  PhotonMap global_, caustic_;
  const Scene* scene_ = nullptr;
};

// Builds a photon map from `paths` photon paths; `causticOnly` keeps only
// photons at the end of a specular chain (L S+ D). Deterministic for a seed.
PhotonMap buildPhotonMap(const Scene& scene, uint64_t seed, size_t paths, int maxBounces, bool causticOnly,
                         uint64_t* rays = nullptr);

}  // namespace lb
