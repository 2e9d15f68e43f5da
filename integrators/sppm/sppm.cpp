#include "integrators/sppm/sppm.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/bsdfs/bsdf.h"
#include "integrators/direct_light.h"
#include "integrators/pixel_tiles.h"
#include "integrators/photon_map/photon_map.h"
#include "integrators/photon_map/point_grid.h"
#include "integrators/photon_map/photon_tracing.h"

namespace lb {

SppmSettings SppmSettings::read(Params& p) {
  SppmSettings s;
  // A pass is the unit of progress, of snapshots and of a time budget: 1e8
  // paths already take tens of seconds on two cores, and a pass's deposits
  // grow with it, so beyond that a render goes silent for minutes.
  int photons = p.getInt("photons_per_pass", 100000, {"photon paths traced per pass", Range::between(1, 1e8)});
  s.photonsPerPass = size_t(photons);
  s.alpha = p.getFloat("alpha", 0.7f,
                       {"fraction of new photons kept as the radius shrinks (Hachisuka & Jensen 2009, Eq. 6)",
                        Range::open(0, 1)});
  // Bounded as VCM's radius is (integrators/vcm/vcm.cpp): π·r² must stay finite.
  s.initialRadius = p.getFloat("initial_radius", 0,
                               {"first pass's gather radius in world units; 0: relative_radius", Range::between(0, 1e12)});
  s.relativeRadius = p.getFloat("relative_radius", 0.02f,
                                {"first radius as a fraction of the scene's bounding radius", Range::openClosed(0, 1)});
  s.maxDepth = p.getInt("max_depth", 32, {"longest path in segments, camera to light", Range::atLeast(0)});
  s.gridLookup = p.getChoice("lookup", "grid", {"grid", "flann"},
                             "how visible points near a photon are found: a hash grid or FLANN's kd-tree") == "grid";
  p.checkUnused();
  return s;
}

namespace {
struct VisiblePoint {
  SurfaceInteraction si;
  Color beta{0.f};
  int segments = 0;  // camera segments to the point: photons of max_depth − segments may land here
  bool valid = false;
};
struct Deposit {
  uint32_t pixel;
  Color flux;
};
}  // namespace

void Sppm::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) {
  const int W = film.width(), H = film.height();
  if (pixels_.empty()) {
    float r0 = settings_.initialRadius > 0 ? settings_.initialRadius : settings_.relativeRadius * scene.bounds().radius();
    pixels_.assign(size_t(W) * H, SppmPixel{0, r0, glm::dvec3(0)});
  }
  // 1. Camera pass: visible points, emission through specular chains, NEE.
  std::vector<VisiblePoint> vps(size_t(W) * H);
  PassImage direct(W, H);
  forEachPixel(W, H, prototype, stats, [&](int, int x, int y, Sampler& sampler, uint64_t& rays) {
    sampler.start(uint64_t(y) * W + x, pass);
    Camera::FilmSample at = scene.camera.sampleFilm(x, y, sampler.get2D());
    NonSpecularHit hit = traceToNonSpecular(scene, scene.camera.generateRay(at.raster), sampler, settings_.maxDepth, rays);
    hit.emitted *= at.weight, hit.beta *= at.weight;  // the pixel filter's weight (core/filter.h)
    Color L = hit.emitted;
    if (hit.si && hit.segments < settings_.maxDepth) {  // the visible point: direct light by NEE here
      if (auto d = sampleDirectLight(scene, *hit.si, BSDF(*hit.si), sampler, rays)) L += hit.beta * d->contribution;
      vps[size_t(y) * W + x] = {*hit.si, hit.beta, hit.segments, true};
    }
    direct.add(x, y, L, pass, film);
  });
  film.addPass(direct);

  // 2. Photon pass into the visible points (FLANN over their positions).
  std::vector<Vec3> positions;
  std::vector<float> radii;
  std::vector<uint32_t> pixelOf;
  float maxRadius = 0;
  for (size_t i = 0; i < vps.size(); ++i)
    if (vps[i].valid) {
      positions.push_back(vps[i].si.p);
      radii.push_back(pixels_[i].R);
      pixelOf.push_back(uint32_t(i));
      maxRadius = std::max(maxRadius, pixels_[i].R);
    }
  std::unique_ptr<PointIndex> index;
  std::unique_ptr<PointGrid> grid;
  if (settings_.gridLookup) grid = std::make_unique<PointGrid>(positions, radii, std::max(maxRadius, 1e-30f));
  else index = std::make_unique<PointIndex>(positions);
  size_t M = settings_.photonsPerPass;
  size_t chunks = (M + PhotonPathsPerChunk - 1) / PhotonPathsPerChunk;
  std::vector<std::vector<Deposit>> deposits(chunks);
  // Photons serve camera paths of at least one segment (path_length.h).
  int photonSegments = settings_.maxDepth - 1;
  if (!positions.empty() && photonSegments >= 2)
    stats.rays += tracePhotons(scene, hashValues(prototype.seed(), 0x5995eedULL), pass, M, photonSegments, [&](size_t c, const PhotonHit& h) {
      if (h.bounces == 0) return;  // direct light comes from NEE
      int segments = h.bounces + 1;
      // Shading normals: the photon's flux is per unit geometric area, reflected
      // radiance takes the shading cosine (see PhotonMap::radiance).
      float cosG = absDot(h.wi, h.si->ng);
      if (cosG == 0) return;
      thread_local std::vector<std::pair<size_t, float>> found;
      found.clear();
      if (grid) {
        for (uint32_t k : grid->candidates(h.si->p)) {
          Vec3 d = positions[k] - h.si->p;
          found.push_back({k, glm::dot(d, d)});
        }
      } else {
        index->radius(h.si->p, maxRadius, found);
      }
      for (const auto& [k, d2] : found) {
        uint32_t pixel = pixelOf[k];
        float R = pixels_[pixel].R;
        const VisiblePoint& vp = vps[pixel];
        // Outside its radius, on another surface, or a path longer than max_depth.
        if (d2 > R * R || glm::dot(vp.si.ng, h.si->ng) < 0.5f || vp.segments + segments > settings_.maxDepth) continue;
        Color f = BSDF(vp.si).eval(vp.si.wo, h.wi, TransportMode::Radiance).f;
        Color flux = vp.beta * f * h.beta * (absDot(h.wi, vp.si.shading.n) / cosG);
        if (!isBlack(flux)) deposits[c].push_back({pixel, flux});
      }
    });
  photonsEmitted_ += M;

  // 3. Progressive statistics, merged in chunk order (deterministic).
  std::vector<double> count(pixels_.size(), 0);
  std::vector<glm::dvec3> flux(pixels_.size(), glm::dvec3(0));
  for (const auto& chunk : deposits)
    for (const Deposit& d : chunk) {
      if (!isFinite(d.flux)) {
        film.recordNonFinite(int(d.pixel % W), int(d.pixel / W), pass);
        continue;
      }
      count[d.pixel] += 1;
      flux[d.pixel] += glm::dvec3(d.flux);
    }
  std::vector<glm::dvec3> estimate(pixels_.size());
  for (size_t i = 0; i < pixels_.size(); ++i) {
    pixels_[i].update(count[i], flux[i], settings_.alpha);
    double R = pixels_[i].R;
    estimate[i] = pixels_[i].tau / (double(photonsEmitted_) * Pi * R * R);
  }
  film.setProgressiveEstimate(std::move(estimate));
}

}  // namespace lb
