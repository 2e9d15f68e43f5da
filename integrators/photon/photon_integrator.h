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
#include "integrators/photon_map/photon_map_settings.h"

namespace lb {

struct PhotonSettings : PhotonMapSettings {
  int finalGather = 8;
  int maxDepth = 32;
  bool densityImages = false, stats = false;
  static PhotonSettings read(Params& p);
};

class PhotonMapper final : public PixelIntegrator {
 public:
  std::string splitRefusal() const override {
    return "its photon maps are built once per render; each chunk would trace and pay for its own maps";
  }
  explicit PhotonMapper(PhotonSettings s) : settings_(s) {}
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  std::vector<std::string> writeExtraOutputs(const std::string& stem) const override;
  std::vector<std::string> extraOutputPaths(const std::string& stem) const override;
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

}  // namespace lb
