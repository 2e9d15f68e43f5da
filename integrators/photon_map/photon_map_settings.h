#pragma once
// The photon maps' settings and construction, shared by photon mapping
// (integrators/photon/) and the irradiance cache's photon records
// (integrators/irradiance_cache/, base: photon).
#include <cstdint>
#include <string>
#include "core/params.h"
#include "core/progress.h"
#include "core/scene.h"
#include "integrators/photon_map/photon_map.h"

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

// Builds a photon map from `paths` photon paths; `causticOnly` keeps only
// photons at the end of a specular chain (L S+ D). Deterministic for a seed.
PhotonMap buildPhotonMap(const Scene& scene, uint64_t seed, size_t paths, int maxBounces, bool causticOnly,
                         Progress* progress = nullptr, uint64_t* rays = nullptr);

}  // namespace lb
