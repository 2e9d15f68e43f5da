#include "integrators/photon_map/photon_map_settings.h"
#include "core/memory.h"
#include <atomic>
#include <cstdio>
#include <limits>
#include "integrators/photon_map/photon_tracing.h"

namespace lb {

PhotonMapSettings PhotonMapSettings::read(Params& p) {
  PhotonMapSettings s;
  ConfigError where = p.error("global_photons", "");
  s.file = where.file(), s.line = where.line(), s.key = where.key();
  int global = p.getInt("global_photons", 200000,
                        {"photon paths traced for the global map (indirect light)", Range::atLeast(0)});
  int caustic = p.getInt("caustic_photons", 200000,
                         {"photon paths traced for the caustic map (light via specular chains)", Range::atLeast(0)});
  s.globalPhotons = size_t(global), s.causticPhotons = size_t(caustic);
  int k = p.getInt("k", 30,
                   {"photons per density estimate; 0: every photon within max_radius", Range::atLeast(0), "0, or >= 2"});
  // The k-th photon only sets the radius (photon_map.h): k = 1 estimates nothing.
  // k = 0: no k-th photon, the disc is always max_radius (fixed-radius estimate).
  if (k == 1)
    p.fail("k", "must be 0 (every photon within max_radius) or at least 2 (the k-th nearest photon only sets the radius)");
  s.query.k = k == 0 ? std::numeric_limits<size_t>::max() : size_t(k);
  s.maxRadius = p.getFloat("max_radius", 0,
                           {"largest gather radius in world units; 0: 5 % of the scene's bounding radius",
                            Range::between(0, 1e12)});
  return s;
}

DensityQuery PhotonMapSettings::queryFor(const Scene& scene) const {
  DensityQuery q = query;
  q.maxRadius = maxRadius > 0 ? maxRadius : 0.05f * scene.bounds().radius();
  return q;
}

void PhotonMapSettings::checkMemory(const Scene& scene, uint64_t seed, int maxBounces) const {
  // Each stored photon: itself twice while the map is merged, FLANN's copy of
  // its position, and FLANN's index and tree (about two words).
  const double bytesPerPhoton = 2 * sizeof(Photon) + 3 * sizeof(float) + 2 * sizeof(size_t);
  const double limit = 0.9 * availableMemoryBytes();
  double requested = double(globalPhotons) + double(causticPhotons);
  // A path stores at most one photon per bounce: if even that fits, no pilot is needed.
  if (requested * double(maxBounces) * bytesPerPhoton <= limit || requested <= PhotonPathsPerChunk) return;
  std::atomic<uint64_t> stored{0}, causticStored{0};
  tracePhotons(scene, seed, 7, PhotonPathsPerChunk, maxBounces, [&](size_t, const PhotonHit& h) {
    ++stored;
    if (h.specularChain) ++causticStored;
  });
  double photons = double(stored) / PhotonPathsPerChunk * double(globalPhotons) +
                   double(causticStored) / PhotonPathsPerChunk * double(causticPhotons);
  double bytes = photons * bytesPerPhoton;
  if (bytes > limit) {
    char msg[256];
    std::snprintf(msg, sizeof msg,
                  "%zu global + %zu caustic photon paths would store about %.3g photons (%.1f GiB with the kd-tree), "
                  "more than 90%% of the %.1f GiB of memory available; request fewer photons",
                  globalPhotons, causticPhotons, photons, bytes / (1 << 30), limit / 0.9 / (1 << 30));
    throw ConfigError(file, line, key, msg);
  }
}

PhotonMap buildPhotonMap(const Scene& scene, uint64_t seed, size_t paths, int maxBounces, bool causticOnly,
                         Progress* progress, uint64_t* rays) {
  size_t chunks = (paths + PhotonPathsPerChunk - 1) / PhotonPathsPerChunk;
  std::vector<std::vector<Photon>> perChunk(chunks);
  uint64_t traced = tracePhotons(scene, seed, causticOnly ? 1 : 0, paths, maxBounces, [&](size_t c, const PhotonHit& h) {
    if (causticOnly && !h.specularChain) return;
    perChunk[c].push_back({h.si->p, h.wi, h.beta / float(paths), h.si->ng, h.bounces + 1});
  }, progress, causticOnly);
  if (rays) *rays = traced;
  std::vector<Photon> all;
  for (auto& c : perChunk) all.insert(all.end(), c.begin(), c.end());  // chunk order: deterministic
  return PhotonMap(std::move(all));
}

}  // namespace lb
