#include "integrators/vcm/vcm.h"
#include <chrono>
#include <cmath>
#include "core/bsdfs/bsdf.h"
#include "integrators/bidirectional/cost_split.h"
#include "integrators/bidirectional/subpaths.h"
#include "integrators/photon_map/photon_map.h"
#include "integrators/photon_map/hash_grid.h"
#include "integrators/pixel_tiles.h"
#include <tbb/task_arena.h>

namespace lb {

using bidir::Vertex;
using bidir::VertexType;

VcmSettings VcmSettings::read(Params& p) {
  VcmSettings s;
  std::string mode = p.getChoice("mode", "vcm", {"vcm", "bpm", "ppm", "bpt", "lvc"},
                                 "strategies: all, merging only (bidirectional / progressive photon mapping), "
                                 "connections only (Georgiev et al. 2012), or connections to light vertices drawn "
                                 "from all of the pass's (light-vertex-cache BDPT, Davidovic et al. 2014)");
  s.mode = mode == "vcm"   ? VcmMode::Vcm
           : mode == "bpm" ? VcmMode::Bpm
           : mode == "ppm" ? VcmMode::Ppm
           : mode == "bpt" ? VcmMode::Bpt
                           : VcmMode::Lvc;
  if (s.mode == VcmMode::Lvc || p.describing()) {
    p.setCondition("mode: lvc");
    s.cacheConnections = p.getInt("connections", 1,
                                  {"light vertices drawn from the pass's cache for each camera vertex to connect to",
                                   Range::between(1, 64)});
    p.setCondition("");
  }
  s.length = PathLength::read(p);
  std::string mis = p.getChoice("mis", "power", {"power", "balance"}, "MIS heuristic over all strategies");
  s.mis = mis == "power" ? bidir::MisWeighting::Power : bidir::MisWeighting::Balance;
  // The bounds keep N·π·r² (the merging strategy's density, in float) finite
  // for any film that fits in memory: radius=1e30 gave NaN samples and a
  // black image (issue 34); a radius beyond the scene's is no radius at all.
  s.radius = p.getFloat("radius", 0,
                        {"first pass's merging radius in world units; 0: relative_radius", Range::between(0, 1e12)});
  s.relativeRadius = p.getFloat("relative_radius", s.relativeRadius,
                                {"first radius as a fraction of the scene's bounding radius", Range::openClosed(0, 1)});
  s.alpha = p.getFloat("alpha", s.alpha,
                       {"radius after n passes: r1 n^((alpha-1)/2); 1 keeps it fixed (Georgiev et al. 2012, Eq. 16)",
                        Range::openClosed(0, 1)});
  s.gridLookup = p.getChoice("lookup", "grid", {"grid", "flann"},
                             "how light vertices near a camera vertex are found: a hash grid or FLANN's kd-tree") == "grid";
  s.regularization = RegularizationSettings::read(p);
  p.checkUnused();
  return s;
}

Vcm::Vcm(VcmSettings s) : settings_(s) {
  if (s.regularization.enabled) regularization_ = std::make_unique<Regularization>(s.regularization);
}

float Vcm::radius(const Scene& scene, uint64_t pass) const {
  float r1 = settings_.radius > 0 ? settings_.radius : settings_.relativeRadius * scene.bounds().radius();
  return r1 * float(std::pow(double(pass + 1), (double(settings_.alpha) - 1) / 2));
}

namespace {

// A light vertex in the merging index: its tile's array, where its light
// subpath starts there, and its place on the subpath.
struct LightVertexRef {
  uint32_t tile, first, index;
};

}  // namespace

void Vcm::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) {
  const int W = film.width(), H = film.height();
  const size_t N = size_t(W) * size_t(H);  // light subpaths per iteration
  const float r = radius(scene, pass);
  const double mergeNorm = 1 / (double(N) * Pi * double(r) * r);
  bidir::Techniques techniques{settings_.connections(), settings_.merging() ? float(double(N) * Pi * r * r) : 0.f};
  const bool cache = settings_.mode == VcmMode::Lvc;
  const int k = settings_.cacheConnections;
  // lvc: the weights count a connection k·N/M times, with M from the pass
  // before (mode lvc in vcm.h).
  if (cache) techniques.connectionCount = double(k) * double(N) / double(cachedBefore_ > 0 ? cachedBefore_ : N);
  if (cache && settings_.weightCountOverride > 0) techniques.connectionCount = settings_.weightCountOverride;
  const int maxSeg = settings_.length.maxSegments();
  // "Unlimited" depth is capped at 4096 segments: the subpaths' arrays (as in bdpt).
  const size_t cameraCapacity = size_t(std::min(maxSeg, 1 << 12)) + 1;
  const size_t lightCapacity = std::max<size_t>(1, cameraCapacity - 1);
  const bool weighted = settings_.mode != VcmMode::Ppm;  // ppm: merging alone, weight 1
  // regularize: this pass's twins, used by both walks as bdpt's are
  // (core/bsdfs/regularization.h). A merge joins the light subpath to a
  // camera vertex and evaluates only that vertex's BSDF: mergeable only if
  // non-delta or a twin, i.e. with a non-delta vertex on the camera's side,
  // so the light subpath's twins are the ones the rule asks for; t = 1 may
  // not end at a twin (connect.cpp), as in bdpt.
  if (regularization_) regularization_->prepare(scene, pass);
  const Regularization* regularization = regularization_.get();

  // 1. Light subpaths, one per pixel, from a stream apart from the pixel's
  //    camera subpath; with connections, each vertex is joined to the camera.
  //    Each tile appends its pixels' subpaths to one array of its own (no
  //    vector per pixel, and the same layout whatever the thread count),
  //    and lists the vertices photons can be merged at.
  const size_t tiles = size_t(tileCount(W, H));
  tileVertices_.resize(tiles);
  lightSubpaths_.resize(N);
  std::vector<std::vector<Splat>> splats(tiles);
  std::vector<std::vector<Vec3>> tilePoints(tiles);
  std::vector<std::vector<LightVertexRef>> tileRefs(tiles);
  for (auto& v : tileVertices_) v.clear();
  forEachPixel(W, H, prototype, stats, [&](int tile, int x, int y, Sampler& sampler, uint64_t& rays) {
    bidir::PhaseScope phase(bidir::Phase::LightSubpaths);
    thread_local std::vector<Vertex> light, cameraEnd(1);
    light.resize(lightCapacity);
    size_t pixel = size_t(y) * W + x;
    sampler.start(N + pixel, pass);
    int n = bidir::generateLightSubpath(scene, sampler, settings_.length, light, rays, {}, regularization);
    if (weighted) bidir::computePartialSums(scene, settings_.mis, techniques, light, n, bidir::SubpathSide::Light);
    if (settings_.connections())
      for (int s = 2; s <= n && s <= maxSeg; ++s) {  // t = 1: s segments
        bidir::Connection c = bidir::connect(scene, sampler, settings_.mis, techniques, light, cameraEnd, s, 1, rays);
        Color v = c.L * c.weight;
        if (isBlack(v)) continue;
        if (!isFinite(v)) {
          film.recordNonFinite(x, y, pass);
          continue;
        }
        splats[size_t(tile)].push_back({c.raster, v});
      }
    std::vector<Vertex>& stored = tileVertices_[size_t(tile)];
    uint32_t first = uint32_t(stored.size());
    stored.insert(stored.end(), light.begin(), light.begin() + n);
    lightSubpaths_[pixel] = {uint32_t(tile), first, uint32_t(n)};
    // (ppm merges only at a camera walk's first non-delta vertex, never at a
    // twin: photons on twins would only leak into nearby diffuse surfaces.)
    if (settings_.merging())
      for (int j = 1; j < n; ++j)
        if (light[size_t(j)].mergeable() && !(light[size_t(j)].regularized && settings_.mode == VcmMode::Ppm))
          tilePoints[size_t(tile)].push_back(light[size_t(j)].p), tileRefs[size_t(tile)].push_back({uint32_t(tile), first, uint32_t(j)});
    // lvc: the cache, every vertex a camera vertex can connect to within
    // max_depth (s = j + 1 light vertices and t >= 2: j + 2 segments at least).
    if (cache)
      for (int j = 1; j < n && j + 2 <= maxSeg; ++j)
        if (light[size_t(j)].connectible() && light[size_t(j)].type == VertexType::Surface)
          tileRefs[size_t(tile)].push_back({uint32_t(tile), first, uint32_t(j)});
  });

  // 2. The merging index over every light vertex photons can be merged at,
  //    in tile order.
  using Clock = std::chrono::steady_clock;
  Clock::time_point indexStart = Clock::now();
  std::vector<Vec3> points;
  std::vector<LightVertexRef> refs;
  for (size_t k = 0; k < tiles; ++k) {
    points.insert(points.end(), tilePoints[k].begin(), tilePoints[k].end());
    refs.insert(refs.end(), tileRefs[k].begin(), tileRefs[k].end());
  }
  std::unique_ptr<HashGrid> grid;
  std::unique_ptr<PointIndex> index;
  if (settings_.merging() && settings_.gridLookup) grid = std::make_unique<HashGrid>(points, r);
  else if (settings_.merging()) index = std::make_unique<PointIndex>(points);
  bidir::CostSplit::charge(bidir::Phase::Index, std::chrono::duration<double>(Clock::now() - indexStart).count() *
                                                   tbb::this_task_arena::max_concurrency());

  // lvc: a draw from the cache counts k·N/M times per camera sample.
  const float perDraw = float(double(refs.size()) / (double(k) * double(N)));

  // 3. Camera subpaths: connections to the pixel's own light subpath, merges
  //    with every light vertex within r.
  PassImage image(W, H, &scene.camera.filter());
  forEachPixel(W, H, prototype, stats, [&](int, int x, int y, Sampler& sampler, uint64_t& rays) {
    bidir::PhaseScope phase(bidir::Phase::CameraSubpaths);
    thread_local std::vector<Vertex> camera;
    thread_local std::vector<std::pair<size_t, float>> found;
    camera.resize(cameraCapacity);
    size_t pixel = size_t(y) * W + x;
    sampler.start(pixel, pass);
    Camera::FilmSample at = scene.camera.sampleFilm(x, y, sampler.get2D());
    // Progressive photon mapping merges at the first non-specular vertex
    // only, and weighs nothing: its camera walk ends there, without sums.
    int nc = bidir::generateCameraSubpath(scene, sampler, settings_.length, at.raster, camera, rays, {},
                                          weighted ? bidir::WalkStop::AtLength : bidir::WalkStop::AtFirstNonSpecular,
                                          regularization);
    if (weighted) bidir::computePartialSums(scene, settings_.mis, techniques, camera, nc, bidir::SubpathSide::Camera);
    const LightSubpathRef& own = lightSubpaths_[pixel];
    bidir::Subpath light(tileVertices_[own.tile].data() + own.first, own.count);
    int nl = int(own.count);
    Color L(0.f);
    auto add = [&](const Color& v) {
      if (isFinite(v)) L += v;
      else film.recordNonFinite(x, y, pass);
    };
    // Merging camera[t-1] with every light vertex within r; weight 1 in ppm
    // mode (the only technique there).
    auto mergeAt = [&](int t) {
      bidir::PhaseScope merging(bidir::Phase::Merges);
      const Vertex& pt = camera[size_t(t - 1)];
      found.clear();
      if (grid) {
        grid->forEachWithin(pt.p, [&](uint32_t k, float d2) { found.push_back({k, d2}); });
      } else {
        index->radius(pt.p, r, found);
        // In index order, as the grid gives them: both lookups sum the same
        // merges in the same order, so they render the same image bit for bit.
        std::sort(found.begin(), found.end());
      }
      BSDF bsdf(pt.si);
      for (const auto& [k, d2] : found) {
        const LightVertexRef& ref = refs[k];
        int s = int(ref.index);  // light vertices before the merged one
        if (s + t - 1 > maxSeg) continue;
        bidir::Subpath path(tileVertices_[ref.tile].data() + ref.first, size_t(s) + 1);
        const Vertex& q = path[ref.index];
        // The photon's incoming direction: towards the light subpath's previous vertex.
        Vec3 wl = q.si.wo;
        float cosG = absDot(wl, pt.ng);
        if (cosG == 0) continue;
        BSDFEval e = bsdf.eval(pt.si.wo, wl, TransportMode::Radiance);
        if (isBlack(e.f)) continue;
        // Shading normals: flux arrives per geometric area (photon_map.h).
        Color v = pt.beta * e.f * q.beta * float(mergeNorm * absDot(wl, pt.si.shading.n) / cosG);
        if (weighted) {
          // The camera vertex's densities towards the light subpath, along the
          // photon's direction (Georgiev's report does the same), from the
          // evaluation above; light[s-2]'s reverse density stays as cached.
          bidir::ConnectionDensities rev;
          rev.pt = q.pdfFwd;
          if (t >= 3) rev.ptMinus = bidir::convertDensity(pt, e.pdfRev, camera[size_t(t - 2)]);
          rev.qs = bidir::convertDensity(pt, e.pdf, path[size_t(s - 1)]);
          if (s >= 2) rev.qsMinus = path[size_t(s - 2)].pdfRev;
          v *= bidir::techniqueWeights(scene, settings_.mis, techniques, path, camera, Vertex{}, s, t, rev, &q).mergeAtCamera;
        }
        add(v);
      }
    };
    if (settings_.mode == VcmMode::Ppm) {
      // Through specular vertices to the first non-specular one: lights seen
      // on the way count directly, the rest is merged there.
      for (int t = 2; t <= nc; ++t) {
        const Vertex& v = camera[size_t(t - 1)];
        // An emitter seen on the way (s = 0), unweighted: no densities needed.
        if (v.isLight()) add(v.beta * bidir::emitted(scene, v, camera[size_t(t - 2)]));
        if (v.mergeable()) {
          mergeAt(t);
          break;
        }
        if (!v.delta) break;
      }
    } else {
      for (int t = 2; t <= nc; ++t) {
        // lvc: only s = 0 and s = 1 from this pixel's own samples; s >= 2 from the cache below.
        for (int s = 0; s <= (cache ? 1 : std::max(nl, 1)); ++s) {
          int segments = s + t - 1;
          if ((s >= 1 && !settings_.connections()) || segments > maxSeg) continue;
          bidir::Connection c = bidir::connect(scene, sampler, settings_.mis, techniques, light, camera, s, t, rays);
          if (!isBlack(c.L) && c.weight > 0) add(c.L * c.weight);
        }
        // lvc: k light vertices drawn uniformly from the M cached, each
        // connection divided by its expected count per sample, k·N/M. A draw
        // whose path would pass max_depth is that technique's zero, not redrawn.
        if (cache && !refs.empty())
          for (int draw = 0; draw < k; ++draw) {
            size_t m = std::min(size_t(sampler.get1D() * float(refs.size())), refs.size() - 1);
            const LightVertexRef& ref = refs[m];
            int s = int(ref.index) + 1;
            if (s + t - 1 > maxSeg) continue;
            bidir::Subpath prefix(tileVertices_[ref.tile].data() + ref.first, size_t(s));
            bidir::Connection c = bidir::connect(scene, sampler, settings_.mis, techniques, prefix, camera, s, t, rays);
            if (!isBlack(c.L) && c.weight > 0) add(c.L * (c.weight * perDraw));
          }
        // A merge uses s >= 1 light vertices, s + t − 1 segments: none fits beyond t = max_depth.
        if (settings_.merging() && t <= maxSeg && camera[size_t(t - 1)].mergeable()) mergeAt(t);
      }
    }
    image.add(x, y, L * at.weight, pass, film);  // this tile owns pixel (x, y); the filter's weight (core/filter.h)
  });
  for (const auto& tileSplats : splats)  // fixed order: deterministic sums; t = 1 through the filter
    for (const Splat& s : tileSplats) image.splat(s.raster, s.value, pass, film);
  film.addPass(image);
  if (cache) cachedBefore_ = refs.size();
}

}  // namespace lb
