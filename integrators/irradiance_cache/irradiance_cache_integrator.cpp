#include "integrators/irradiance_cache/irradiance_cache_integrator.h"
#include <chrono>
#include <iostream>
#include "core/format.h"
#include "core/bsdfs/bsdf.h"
#include "core/image.h"
#include "integrators/direct_light.h"
#include "integrators/photon_map/photon_tracing.h"
#include "integrators/pixel_tiles.h"

namespace lb {

IrradianceCacheSettings IrradianceCacheSettings::read(Params& p) {
  IrradianceCacheSettings s;
  // Above 1, Ward's weight would accept records whose normal is turned more
  // than 90° away (sqrt(1 − n·nᵢ) < a): records from other walls.
  s.cache.a = p.getFloat("a", 0.15f, {"Ward's error bound: larger reuses records further away (Ward 1988, Eq. 5)",
                                      Range::openClosed(0, 1)});
  s.cache.spacingInPixels = p.getChoice("spacing", "pixels", {"pixels", "world"},
                                        "units of min_spacing and max_spacing") == "pixels";
  s.cache.minSpacing = p.getFloat("min_spacing", 2, {"smallest record radius", Range::atLeast(0)});
  s.cache.maxSpacing = p.getFloat("max_spacing", 64, {"largest record radius (at least min_spacing)", Range::above(0)});
  if (!(s.cache.maxSpacing >= s.cache.minSpacing)) p.fail("max_spacing", "must be at least min_spacing");
  s.strata.theta = p.getInt("theta_strata", 16, {"hemisphere strata in theta per record", Range::between(1, 1024)});
  s.strata.phi = p.getInt("phi_strata", 48, {"hemisphere strata in phi per record", Range::between(1, 1024)});
  s.cache.gradients = p.getBool("gradients", true, "rotation and translation gradients (Ward & Heckbert 1992)");
  s.cache.neighbourClamping = p.getBool("neighbour_clamping", true,
                                        "clamp a record's radius by its neighbours' (Krivanek et al. 2008)");
  s.prepassLevels = p.getInt("prepass_levels", 3, {"coarse-to-fine prepass levels", Range::between(0, 8)});
  s.base = p.getChoice("base", "path", {"path", "photon"},
                       "what a record's hemisphere rays read: path-traced radiance or the photon map") == "path"
               ? CacheBase::Path
               : CacheBase::Photon;
  s.recordImage = p.getBool("record_image", true, "also write an image of the record positions");
  s.length = PathLength::read(p);
  // Else its keys are rejected as unknown; listed when describing (base: photon only).
  if (s.base == CacheBase::Photon || p.describing()) {
    p.setCondition("base: photon");
    s.photonMaps = PhotonMapSettings::read(p);
  }
  p.checkUnused();
  return s;
}

namespace {
PathTracerSettings baseEstimator(const PathLength& length) {
  PathTracerSettings s;  // BSDF sampling, NEE, power-heuristic MIS
  s.length = length;
  return s;
}
// Only purely Lambertian surfaces are cached (f does not depend on directions).
bool isCached(const BSDF& bsdf) { return bsdf.flags() == (BSDFReflection | BSDFDiffuse); }
// Sample indices reserved for the prepass levels, far from any render pass.
constexpr uint64_t PrepassSample = uint64_t(1) << 48;
double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

IrradianceCacheIntegrator::IrradianceCacheIntegrator(IrradianceCacheSettings s)
    : settings_(s), base_(baseEstimator(s.length)) {}

void IrradianceCacheIntegrator::preprocess(const Scene& scene, const Sampler& prototype) {
  scene_ = &scene;
  seed_ = prototype.seed();
  cache_ = std::make_unique<IrradianceCache>(settings_.cache, scene.bounds());
  stats_ = {};
  const Camera& cam = scene.camera;
  Vec2 centre(0.5f * cam.width(), 0.5f * cam.height());
  // The angle between neighbouring pixels' rays, in double: acos of a float
  // dot product rounds to 0 for images a few thousand pixels wide.
  glm::dvec3 a(cam.generateRay(centre).d), b(cam.generateRay(centre + Vec2(1, 0)).d);
  pixelAngle_ = float(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
  if (settings_.base == CacheBase::Photon) {
    query_ = settings_.photonMaps.queryFor(scene);
    uint64_t seed = hashValues(seed_, 0x1cac4e);
    int photonSegments = std::max(0, settings_.length.maxSegments() - 1);  // camera paths have at least one
    settings_.photonMaps.checkMemory(scene, seed, photonSegments);
    Progress progress("photon tracing", double(settings_.photonMaps.globalPhotons + settings_.photonMaps.causticPhotons),
                      progress_);
    global_ = buildPhotonMap(scene, seed, settings_.photonMaps.globalPhotons, photonSegments, false, &progress);
    caustic_ = buildPhotonMap(scene, seed + 1, settings_.photonMaps.causticPhotons, photonSegments, true, &progress);
    progress.finish();
  }
  // Lazy creation, coarse to fine (Tabellion & Lamorlette 2004): sparse pixels
  // first, so the records they create cover most of the image before the
  // full-resolution passes need them.
  auto t0 = std::chrono::steady_clock::now();
  PassStats ignored;
  // Level L visits one pixel in 4^L: its share of the prepass's work.
  double work = 0;
  for (int level = settings_.prepassLevels; level >= 1; --level) work += 1.0 / double(1 << (2 * level));
  Progress progress("irradiance cache prepass", work, progress_);
  for (int level = settings_.prepassLevels; level >= 1; --level) {
    runPass(nullptr, 1 << level, PrepassSample + uint64_t(level), prototype, ignored, {});
    progress.advance(1.0 / double(1 << (2 * level)));
  }
  progress.finish();
  stats_.prepassRecords = cache_->size();
  stats_.prepassSeconds = secondsSince(t0);
}

void IrradianceCacheIntegrator::runPass(const Film* film, int stride, uint64_t sampleIndex, const Sampler& prototype,
                                        PassStats& stats, const std::function<void(int, int, const Color&)>& result) {
  const Camera& cam = scene_->camera;
  int w = (cam.width() + stride - 1) / stride, h = (cam.height() + stride - 1) / stride;
  std::vector<LocalRecords> tiles(size_t(tileCount(w, h)));
  forEachPixel(w, h, prototype, stats, [&](int tile, int i, int j, Sampler& sampler, uint64_t& rays) {
    int x = std::min(i * stride + stride / 2, cam.width() - 1), y = std::min(j * stride + stride / 2, cam.height() - 1);
    uint64_t pixel = uint64_t(y) * cam.width() + x;
    sampler.start(pixel, sampleIndex);
    // Jittered in the prepass too: exact pixel centres fall on the seams and
    // diagonals of axis-aligned scenes, where a record belongs to no single surface.
    Camera::FilmSample at = cam.sampleFilm(x, y, sampler.get2D());
    Color L = Li(cam.generateRay(at.raster), sampler, hashValues(seed_, pixel, sampleIndex), tiles[tile], rays) * at.weight;
    if (result) result(x, y, L);
  });
  for (const LocalRecords& t : tiles) {
    stats_.lookups += t.lookups, stats_.hits += t.hits;
    stats_.lookupSeconds += t.lookupSeconds, stats_.recordSeconds += t.recordSeconds;
    stats_.nonFiniteIncident += t.nonFinite;
  }
  cache_->merge(tiles);
}

void IrradianceCacheIntegrator::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass,
                                          PassStats& stats) {
  scene_ = &scene;
  film_ = &film;
  runPass(&film, 1, pass, prototype, stats, [&](int x, int y, const Color& L) { film.addSample(x, y, pass, L); });
}

std::optional<Color> IrradianceCacheIntegrator::replaySample(const Scene& scene, const Sampler& prototype, int x,
                                                             int y, uint64_t sample) {
  if (!cache_) preprocess(scene, prototype);
  auto sampler = prototype.clone();
  uint64_t pixel = uint64_t(y) * scene.camera.width() + x, rays = 0;
  sampler->start(pixel, sample);
  Camera::FilmSample at = scene.camera.sampleFilm(x, y, sampler->get2D());
  // The replay sees the cache as it is now (after a render: every record) and
  // none of the records its tile had made earlier in the pass, so it
  // reproduces the rendered sample only where the cache already covered it.
  LocalRecords local;
  return Li(scene.camera.generateRay(at.raster), *sampler, hashValues(seed_, pixel, sample), local, rays) * at.weight;
}

Color IrradianceCacheIntegrator::Li(const Ray& cameraRay, Sampler& sampler, uint64_t key, LocalRecords& local,
                                    uint64_t& rays) const {
  const Scene& scene = *scene_;
  const LightSampler& lights = scene.lightSampler();
  Color L(0.f), beta(1.f);
  Ray ray = cameraRay;
  bool prevDelta = true;
  float prevPdf = 0, etaScale = 1;
  Vec3 prevPoint = ray.o;
  int maxDepth = settings_.length.maxSegments();
  for (int segments = 1; segments <= maxDepth; ++segments) {
    SurfaceInteraction si;
    ++rays;
    bool hit = scene.intersect(ray, si);
    auto emissionWeight = [&](const Light* light, float pdfLi) {
      return prevDelta ? 1.f : powerHeuristic(prevPdf, lights.pmf(light) * pdfLi);
    };
    if (!hit) {
      for (const Light* env : scene.infiniteLights())
        L += beta * env->Le(ray.d) * emissionWeight(env, env->pdfLi(prevPoint, ray.d, {}, {}));
      break;
    }
    if (si.emitter) {
      Color Le = si.emitter->L(si.ng, si.wo);
      if (!isBlack(Le)) L += beta * Le * emissionWeight(si.emitter, si.emitter->pdfLi(prevPoint, ray.d, si.p, si.ng));
    }
    if (segments == maxDepth || !si.material) break;
    BSDF bsdf(si);

    if (isCached(bsdf)) {
      // Direct light by NEE alone: no BSDF-sampled ray leaves x to be its MIS partner.
      if (auto d = sampleDirectLight(scene, si, bsdf, sampler, rays)) L += beta * d->contribution;
      Vec3 n = glm::dot(si.wo, bsdf.shadingNormal()) < 0 ? -bsdf.shadingNormal() : bsdf.shadingNormal();
      thread_local std::vector<std::pair<size_t, float>> scratch;
      if (settings_.base == CacheBase::Photon)
        L += beta * caustic_.radiance(si, query_, maxDepth - segments, [&](const Vec3& wi) { return bsdf.eval(si.wo, wi, TransportMode::Radiance).f; }, scratch);
      Color E = irradiance(si, n, key, maxDepth - segments, local, rays);
      L += beta * bsdf.eval(si.wo, n, TransportMode::Radiance).f * E;
      break;
    }

    // Glossy and specular surfaces: as in the path tracer (NEE + power-heuristic MIS).
    if (!bsdf.isDelta())
      if (auto d = sampleDirectLight(scene, si, bsdf, sampler, rays))
        L += beta * d->contribution * (d->deltaLight ? 1.f : powerHeuristic(d->lightPdf, d->bsdfPdf));
    float uLobe = sampler.get1D();
    auto bs = bsdf.sample(si.wo, uLobe, sampler.get2D(), TransportMode::Radiance);
    if (!bs) break;
    beta *= bs->weight;
    if (bs->lobe & BSDFTransmission) etaScale *= sqr(bs->eta);
    prevPdf = bs->pdf;
    prevDelta = bs->isDelta();
    prevPoint = si.p;
    ray = si.spawnRay(bs->wi);
    if (isBlack(beta)) break;
    if (!settings_.length.survivesRoulette(segments, beta, etaScale, sampler)) break;
  }
  return L;
}

Color IrradianceCacheIntegrator::irradiance(const SurfaceInteraction& si, const Vec3& n, uint64_t key,
                                            int segmentsLeft, LocalRecords& local, uint64_t& rays) const {
  if (segmentsLeft < 2) return Color(0.f);  // x → y → light needs two more segments
  // A record holds paths of up to segmentsLeft segments: it serves only this budget (path_length.h).
  int budget = settings_.length.maxDepth < 0 ? -1 : segmentsLeft;
  auto t0 = std::chrono::steady_clock::now();
  Color E;
  bool found = cache_->interpolate(si.p, n, local, E, budget);
  local.lookupSeconds += secondsSince(t0);
  ++local.lookups;
  if (found) {
    ++local.hits;
    return E;
  }
  t0 = std::chrono::steady_clock::now();
  IrradianceRecord r = computeRecordAt(si, key, segmentsLeft, rays, &local.nonFinite);
  float worldPerPixel = pixelAngle_ * glm::length(si.p - scene_->camera.position());
  cache_->clampRadius(r, worldPerPixel);
  r.segmentsLeft = budget;
  local.records.push_back(r);
  local.recordSeconds += secondsSince(t0);
  return r.E;
}

IrradianceRecord IrradianceCacheIntegrator::computeRecordAt(const SurfaceInteraction& si, uint64_t key,
                                                            int segmentsLeft, uint64_t& rays, uint64_t* dropped) const {
  Vec3 ns = si.shading.n;
  Vec3 n = glm::dot(si.wo, ns) < 0 ? -ns : ns;
  Pcg32 rng(key, 0x7ec0);
  IndependentSampler sampler(seed_);
  IrradianceRecord r = computeRecord(
      si.p, n, settings_.strata, rng, [&](const Vec3& d) { return si.spawnRay(d); },
      [&](const Ray& ray, uint64_t direction) {
        sampler.start(key, direction);
        IncidentSample s = incident(ray, sampler, segmentsLeft, rays);
        if (!std::isfinite(s.L.r + s.L.g + s.L.b)) {  // never let one sample poison a record
          s.L = Color(0.f);
          if (dropped) ++*dropped;
        }
        return s;
      });
  return r;
}

IncidentSample IrradianceCacheIntegrator::incident(const Ray& ray, Sampler& sampler, int segmentsLeft,
                                                   uint64_t& rays) const {
  if (settings_.base == CacheBase::Photon) return photonIncident(ray, sampler, segmentsLeft, rays);
  IncidentSample s;
  s.L = base_.incidentRadiance(ray, *scene_, sampler, rays, segmentsLeft, false, &s.distance);
  return s;
}

IncidentSample IrradianceCacheIntegrator::photonIncident(const Ray& ray, Sampler& sampler, int segmentsLeft,
                                                         uint64_t& rays) const {
  // As photon mapping's final gather: through specular surfaces to the first
  // non-specular one, whose reflected radiance the global map estimates.
  // Emission met on the way is left out: straight from an emitter it is
  // direct light (NEE at x), through specular surfaces a caustic (caustic map).
  // The walk and the photon share segmentsLeft; a photon has at least one.
  thread_local std::vector<std::pair<size_t, float>> scratch;
  NonSpecularHit hit = traceToNonSpecular(*scene_, ray, sampler, segmentsLeft - 1, rays);
  IncidentSample s;
  s.distance = hit.firstHitDistance;
  if (hit.si) {
    const SurfaceInteraction& y = *hit.si;
    BSDF at(y);
    s.L = hit.beta * global_.radiance(y, query_, segmentsLeft - hit.segments, [&](const Vec3& wi) { return at.eval(y.wo, wi, TransportMode::Radiance).f; }, scratch);
  }
  return s;
}

std::vector<std::string> IrradianceCacheIntegrator::writeExtraOutputs(const std::string& stem) const {
  if (!cache_) return {};
  const IrradianceCacheStats& s = stats_;
  char hitRate[16];
  std::snprintf(hitRate, sizeof hitRate, "%.1f %%", 100.0 * double(s.hits) / double(std::max<uint64_t>(s.lookups, 1)));
  std::cerr << "irradiance cache: " << formatCount(double(cache_->size())) << " records ("
            << formatCount(double(s.prepassRecords)) << " from the prepass in " << formatSeconds(s.prepassSeconds)
            << "); " << formatCount(double(cache_->size()) / std::max(s.recordSeconds, 1e-9), "records/s")
            << " per thread; " << formatCount(double(s.lookups), "lookups") << ", "
            << formatCount(double(s.lookups) / std::max(s.lookupSeconds, 1e-9), "lookups/s") << " per thread; hit rate "
            << hitRate;
  if (s.nonFiniteIncident) std::cerr << "; " << s.nonFiniteIncident << " NaN/Inf hemisphere samples dropped";
  std::cerr << "\n";
  if (!settings_.recordImage || !film_) return {};
  // The render in grey, each record's position (seen directly from the camera) in red.
  Image img = film_->image();
  for (Color& c : img.pixels) c = Color(0.5f * luminance(c));
  const Camera& cam = scene_->camera;
  for (const IrradianceRecord& r : cache_->records()) {
    auto c = cam.connect(r.p);
    if (!c) continue;
    if (scene_->occluded(Ray{c->pinhole, r.p - c->pinhole, 1 - 1e-3f})) continue;
    int x = int(c->raster.x), y = int(c->raster.y);
    if (x >= 0 && y >= 0 && x < img.width && y < img.height) img.at(x, y) = Color(4.f, 0.f, 0.f);
  }
  std::string path = stem + "_records.png";
  writePng(path, img);
  return {path};
}

}  // namespace lb
