#include "integrators/photon/photon_integrator.h"
#include <iostream>
#include "core/format.h"
#include "core/bsdfs/bsdf.h"
#include "integrators/direct_light.h"
#include "integrators/photon_map/photon_tracing.h"

namespace lb {

PhotonSettings PhotonSettings::read(Params& p) {
  PhotonSettings s;
  static_cast<PhotonMapSettings&>(s) = PhotonMapSettings::read(p);
  std::string filter = p.getChoice("filter", "cone", {"cone", "epanechnikov", "box"},
                                   "density-estimation kernel (Jensen 2001, 7.2)");
  s.query.filter = filter == "cone" ? PhotonFilter::Cone : filter == "box" ? PhotonFilter::Box : PhotonFilter::Epanechnikov;
  s.finalGather = p.getInt("final_gather", 8,
                           {"gather rays per camera hit into the global map; 0: read the global map directly",
                            Range::between(0, 4096)});  // 2e9 ran silently for ever (issue 34)
  s.maxDepth = p.getInt("max_depth", 32, {"longest path in segments, camera to light", Range::atLeast(0)});
  s.densityImages = p.getBool("density_images", false, "also write the photon densities as images");
  s.stats = p.getBool("stats", false, "print the maps' sizes and lookup counts");
  p.checkUnused();
  return s;
}


void PhotonMapper::preprocess(const Scene& scene, const Sampler& prototype) {
  scene_ = &scene;
  query_ = settings_.queryFor(scene);
  // Photon streams derive from the run's seed: repeats with distinct seeds
  // get independent photon maps, so their spread measures the estimator's.
  uint64_t seed = hashValues(prototype.seed(), 0x5eed);
  // Photons are used by camera paths of at least one segment (path_length.h).
  int photonSegments = std::max(0, settings_.maxDepth - 1);
  settings_.checkMemory(scene, seed, photonSegments);
  Progress progress("photon tracing", double(settings_.globalPhotons + settings_.causticPhotons), progress_);
  global_ = buildPhotonMap(scene, seed, settings_.globalPhotons, photonSegments, false, &progress);
  caustic_ = buildPhotonMap(scene, seed + 1, settings_.causticPhotons, photonSegments, true, &progress);
  progress.finish();
  if (settings_.stats)
    for (auto [name, map] : {std::pair{"global", &global_}, std::pair{"caustic", &caustic_}})
      std::cerr << "photon map " << name << ": " << formatCount(double(map->size())) << " photons stored, "
                << formatBytes(double(map->memoryBytes())) << ", kd-tree build " << formatSeconds(map->buildSeconds())
                << "\n";
}


Color PhotonMapper::gather(const Scene& scene, const SurfaceInteraction& x, int segmentsLeft, Sampler& sampler,
                           uint64_t& rays, std::vector<std::pair<size_t, float>>& scratch) const {
  // Every term below is a path of at most segmentsLeft more segments (path_length.h).
  if (segmentsLeft < 1) return Color(0.f);
  BSDF bsdf(x);
  bool glossy = bsdf.flags() & BSDFGlossy;
  const LightSampler& lights = scene.lightSampler();
  int n = settings_.finalGather;
  auto f = [&](const Vec3& wi) { return bsdf.eval(x.wo, wi, TransportMode::Radiance).f; };
  Color L(0.f);
  // Direct light: NEE, MIS-weighted against the gather rays on glossy
  // surfaces (Veach 1997 §9.2.4: n gather samples count n times in the power heuristic).
  if (auto d = sampleDirectLight(scene, x, bsdf, sampler, rays)) {
    float w = glossy && !d->deltaLight && n > 0 ? powerHeuristic(d->lightPdf, float(n) * d->bsdfPdf) : 1.f;
    L += d->contribution * w;
  }
  // Caustics: L S+ D light at x.
  L += caustic_.radiance(x, query_, segmentsLeft, f, scratch);
  // Indirect light: final gathering into the global map. On diffuse surfaces
  // a gather ray needs a photon of at least one segment beyond it.
  if (!glossy && segmentsLeft < 2) return L;
  for (int g = 0; g < n; ++g) {
    Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
    float uLobe = sampler.get1D();
    auto bs = bsdf.sample(x.wo, uLobe, uDir, TransportMode::Radiance);
    if (!bs) continue;
    // The other half of the glossy MIS pair: emission the gather ray reaches directly.
    bool misPartner = glossy && !bs->isDelta();
    auto emitted = [&](const Light* light, const Color& Le, float pdfLi) {
      return bs->weight * Le * powerHeuristic(float(n) * bs->pdf, lights.pmf(light) * pdfLi) / float(n);
    };
    SurfaceInteraction y;
    ++rays;
    Ray ray = x.spawnRay(bs->wi);
    if (!scene.intersect(ray, y)) {
      if (misPartner)
        for (const Light* env : scene.infiniteLights()) L += emitted(env, env->Le(ray.d), env->pdfLi(x.p, ray.d, {}, {}));
      continue;
    }
    if (y.emitter && misPartner) L += emitted(y.emitter, y.emitter->L(y.ng, y.wo), y.emitter->pdfLi(x.p, bs->wi, y.p, y.ng));
    Color weight = bs->weight;
    int gatherSegments = 1;
    if (y.material && y.material->isDelta()) {
      // Light reaching x through specular surfaces from a diffuse one; light
      // arriving straight from an emitter that way is a caustic (caustic map).
      Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
      float uLobe = sampler.get1D();
      auto next = BSDF(y).sample(y.wo, uLobe, uDir, TransportMode::Radiance);
      if (!next) continue;
      NonSpecularHit beyond = traceToNonSpecular(scene, y.spawnRay(next->wi), sampler, segmentsLeft - 2, rays);
      if (!beyond.si) continue;
      weight *= next->weight * beyond.beta;
      gatherSegments += beyond.segments;
      y = *beyond.si;
    }
    if (!y.material) continue;
    BSDF at(y);
    L += weight * global_.radiance(y, query_, segmentsLeft - gatherSegments,
                                   [&](const Vec3& wi) { return at.eval(y.wo, wi, TransportMode::Radiance).f; }, scratch) /
         float(n);
  }
  return L;
}

Color PhotonMapper::Li(const Ray& cameraRay, const Scene& scene, Sampler& sampler, uint64_t& rays) const {
  thread_local std::vector<std::pair<size_t, float>> scratch;
  NonSpecularHit hit = traceToNonSpecular(scene, cameraRay, sampler, settings_.maxDepth, rays);
  if (!hit.si) return hit.emitted;
  const SurfaceInteraction& x = *hit.si;
  int segmentsLeft = settings_.maxDepth - hit.segments;
  if (settings_.finalGather == 0) {  // visualise the global map: all light at x from photons
    BSDF bsdf(x);
    return hit.emitted + hit.beta * global_.radiance(x, query_, segmentsLeft, [&](const Vec3& wi) {
             return bsdf.eval(x.wo, wi, TransportMode::Radiance).f;
           }, scratch);
  }
  return hit.emitted + hit.beta * gather(scene, x, segmentsLeft, sampler, rays, scratch);
}

std::vector<std::string> PhotonMapper::extraOutputPaths(const std::string& stem) const {
  if (!settings_.densityImages) return {};
  std::vector<std::string> paths;
  for (const char* name : {"global", "caustic"})
    for (const char* ext : {".exr", ".png"}) paths.push_back(stem + "_" + name + "_density" + ext);
  return paths;
}

std::vector<std::string> PhotonMapper::writeExtraOutputs(const std::string& stem) const {
  if (!settings_.densityImages || !scene_) return {};
  // Irradiance E = π·(radiance of a white Lambertian) from each map, at the
  // first surface seen through each pixel centre.
  std::vector<std::string> written;
  const Camera& cam = scene_->camera;
  std::vector<std::pair<size_t, float>> scratch;
  for (auto [name, map] : {std::pair{"global", &global_}, std::pair{"caustic", &caustic_}}) {
    Image img(cam.width(), cam.height());
    for (int y = 0; y < cam.height(); ++y)
      for (int x = 0; x < cam.width(); ++x) {
        SurfaceInteraction si;
        if (scene_->intersect(cam.generateRay(Vec2(x + 0.5f, y + 0.5f)), si))
          img.at(x, y) = map->radiance(si, query_, settings_.maxDepth - 1, [](const Vec3&) { return Color(1.f); }, scratch);
      }
    std::string path = stem + "_" + name + "_density.exr";
    writeExr(path, img);
    writePng(stem + "_" + name + "_density.png", img);
    written.push_back(path);
  }
  return written;
}

}  // namespace lb
