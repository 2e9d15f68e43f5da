#include "integrators/guided/guided.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include "integrators/guided/vertex_recorder.h"
#include "integrators/pixel_tiles.h"

namespace lb {

using guiding::GuideVertex;
using guiding::VertexRecorder;

GuidedSettings GuidedSettings::read(Params& p) {
  GuidedSettings s;
  std::string method = p.getChoice("method", "sdtree", {"qlearning", "sdtree"},
                                   "what learns the directions: Q-learning (Dahm & Keller 2017) or an SD-tree "
                                   "(Müller et al. 2017)");
  s.method = method == "qlearning" ? GuidedSettings::Method::QLearning : GuidedSettings::Method::SdTree;
  s.bsdfFraction = p.getFloat(
      "bsdf_fraction", 0.5f,
      {"probability that the BSDF, not the learned distribution, draws a direction", Range::openClosed(0, 1)});
  if (s.method == GuidedSettings::Method::QLearning || p.describing()) {
    p.setCondition("method: qlearning");
    s.qlearning.gridResolution =
        p.getInt("grid_resolution", 32, {"cells of the Q grid along the scene's longest axis", Range::between(1, 128)});
    s.qlearning.rows = p.getInt(
        "q_rows", 8,
        {"rows (of cos θ) of each cell's sphere of Q bins; twice as many columns of φ", Range::between(2, 32)});
    p.setCondition("");
  }
  if (s.method == GuidedSettings::Method::SdTree || p.describing()) {
    p.setCondition("method: sdtree");
    s.sdtree.trainingIterations =
        p.getInt("training_iterations", 5,
                 {"iterations of 1, 2, 4, … spp that train the SD-tree before the image (in the time budget)",
                  Range::between(0, 12)});
    s.sdtree.spatialThreshold =
        p.getFloat("spatial_threshold", 12000.f,
                   {"c: a leaf with more than c·√(2^k) records in iteration k is split", Range::above(0)});
    s.sdtree.subdivisionThreshold =
        p.getFloat("subdivision_threshold", 0.01f,
                   {"ρ: a quadrant with more than this share of a quadtree's energy is subdivided", Range::open(0, 1)});
    s.sdtree.maxQuadTreeDepth = p.getInt("max_quadtree_depth", 20, {"deepest quadtree level", Range::between(1, 20)});
    p.setCondition("");
  }
  std::string debug = p.getString("debug_point", "", "pixel \"x,y\": write the learned distribution seen there");
  if (!debug.empty()) {
    int x = -1, y = -1;
    char end = 0;
    if (std::sscanf(debug.c_str(), "%d,%d%c", &x, &y, &end) != 2 || x < 0 || y < 0)
      p.fail("debug_point", "expected a pixel as \"x,y\" (two non-negative integers), got '" + debug + "'");
    s.debugPoint = std::make_pair(x, y);
  }
  s.path = PathTracerSettings::read(p, false);
  return s;
}

GuidedPathTracer::GuidedPathTracer(GuidedSettings s) : settings_(s), estimator_(s.path) {}

void GuidedPathTracer::preprocess(const Scene& scene, const Sampler& prototype) {
  using Clock = std::chrono::steady_clock;
  auto start = Clock::now();
  scene_ = &scene;
  guides_.clear();  // views of the previous render's method
  trainingPasses_ = 0;
  // Q-learning's later passes sample what the earlier ones taught: unbiased
  // only if their numbers are independent of the earlier ones'.
  // So do all passes with learned roulette and splitting.
  const bool learnsPerPass =
      settings_.method == GuidedSettings::Method::QLearning || settings_.path.rrs != RrsMethod::Classic;
  if (learnsPerPass && !dynamic_cast<const IndependentSampler*>(&prototype))
    throw std::invalid_argument(
        "guided, method qlearning or rrs: adrrs | ears: each pass samples what the earlier passes learned, so "
        "their random numbers must be independent: use sampler type independent");
  estimator_.preprocess(scene, prototype.seed());
  // rrs: adrrs | ears learn from every pass, the SD-tree's training passes included.
  rrs_.reset();
  const PathTracerSettings& ps = settings_.path;
  if (ps.rrs != RrsMethod::Classic)
    rrs_ = std::make_unique<RrsLearning>(ps.rrs, ps.rrsWarmup, scene.bounds(), ps.rrsCells, ps.rrsMinSamples,
                                         scene.camera.width(), scene.camera.height());
  if (settings_.method == GuidedSettings::Method::QLearning) {
    method_ = std::make_unique<guiding::QLearning>(scene.bounds(), settings_.qlearning);
    return;
  }
  auto tree = std::make_unique<guiding::SdTree>(scene.bounds(), settings_.sdtree);
  method_ = std::move(tree);
  auto& sd = static_cast<guiding::SdTree&>(*method_);
  // Training: its own random stream, its images discarded.
  IndependentSampler training(hashValues(prototype.seed(), 0x7a1e5d));
  Film scratch(scene.camera.width(), scene.camera.height());
  PassStats stats;
  for (int k = 0; k < settings_.sdtree.trainingIterations; ++k) {
    for (uint64_t i = 0; i < (uint64_t(1) << k); ++i) pass(scene, scratch, training, trainingPasses_++, stats, true);
    sd.endIteration(k);
  }
  trainingSeconds_ = std::chrono::duration<double>(Clock::now() - start).count();
}

void GuidedPathTracer::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t index,
                                  PassStats& stats) {
  pass(scene, film, prototype, index, stats, settings_.method == GuidedSettings::Method::QLearning);
}

void GuidedPathTracer::pass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t index, PassStats& stats,
                            bool learn) {
  guiding::TileRecords records(learn ? size_t(tileCount(film.width(), film.height())) : 0);
  forEachPixel(film.width(), film.height(), prototype, stats,
               [&](int tile, int x, int y, Sampler& sampler, uint64_t& rays) {
                 sampler.start(uint64_t(y) * uint64_t(scene.camera.width()) + uint64_t(x), index);
                 Camera::FilmSample at = scene.camera.sampleFilm(x, y, sampler.get2D());
                 auto* list = learn ? &records[size_t(tile)] : nullptr;
                 const uint64_t raysBefore = rays;
                 std::optional<RrsView> view;
                 if (rrs_) view = rrs_->view(x, y);
                 Color L = trace(scene.camera.generateRay(at.raster), scene, sampler, localGuide(), list, rays,
                                 view ? &*view : nullptr);
                 if (rrs_) rrs_->recordPixel(x, y, L, double(rays - raysBefore));
                 film.addSample(x, y, index, L * at.weight);
               });
  if (learn) method_->learn(records);
  if (rrs_) rrs_->endPass();
}

DirectionGuide& GuidedPathTracer::localGuide() const {
  auto& guide = guides_.local();
  if (!guide) guide = method_->makeGuide(settings_.bsdfFraction);
  return *guide;
}

Color GuidedPathTracer::Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const {
  return trace(ray, scene, sampler, localGuide(), nullptr, rays);
}

// The path estimator's single-ray loop with the guide in its context, and,
// while learning, a recorder of its vertices.
Color GuidedPathTracer::trace(const Ray& ray, const Scene& scene, Sampler& sampler, DirectionGuide& guide,
                              std::vector<GuideVertex>* records, uint64_t& rays, const RrsView* rrs) const {
  int maxDepth = settings_.path.length.maxSegments();
  if (maxDepth < 1) return Color(0.f);
  PathState s;
  s.ray = ray;
  s.prevPoint = ray.o;
  PathContext c{scene, sampler, maxDepth, true, sampler.dimension(), &guide, nullptr, rrs};
  if (!records) return estimator_.trace(s, c, rays, nullptr);
  VertexRecorder recorder(*records, *method_);
  return estimator_.trace(s, c, rays, &recorder);
}

std::vector<std::string> GuidedPathTracer::summaryLines() const {
  if (!method_) return {};
  std::vector<std::string> lines = method_->statistics();
  if (settings_.method == GuidedSettings::Method::SdTree) {
    char line[160];
    std::snprintf(line, sizeof line, "sd-tree training: %d iterations, %llu spp, %.3g s (in the preprocess)",
                  settings_.sdtree.trainingIterations, (unsigned long long)trainingPasses_, trainingSeconds_);
    lines.push_back(line);
  }
  return lines;
}

std::vector<std::string> GuidedPathTracer::extraOutputPaths(const std::string& stem) const {
  if (!settings_.debugPoint) return {};
  return {stem + "_guide.exr", stem + "_guide.png"};
}

std::vector<std::string> GuidedPathTracer::writeExtraOutputs(const std::string& stem) const {
  if (!settings_.debugPoint || !method_ || !scene_) return {};
  auto [x, y] = *settings_.debugPoint;
  const Camera& camera = scene_->camera;
  if (x >= camera.width() || y >= camera.height()) {
    std::fprintf(stderr, "guided: debug_point %d,%d is outside the %d x %d image; no guide image written\n", x, y,
                 camera.width(), camera.height());
    return {};
  }
  SurfaceInteraction si;
  if (!scene_->intersect(camera.generateRay(Vec2(float(x) + 0.5f, float(y) + 0.5f)), si)) {
    std::fprintf(stderr, "guided: nothing is seen through pixel %d,%d; no guide image written\n", x, y);
    return {};
  }
  Image density = method_->densityImage(si.p, guiding::orientationClass(si), 128);
  writeExr(stem + "_guide.exr", density);
  float peak = 0;
  for (const Color& c : density.pixels) peak = std::max(peak, c.r);
  Image shown = density;
  for (Color& c : shown.pixels) c = peak > 0 ? c / peak : c;
  writePng(stem + "_guide.png", shown);
  std::fprintf(stderr, "guided: learned density at pixel %d,%d (point %g %g %g), peak %g per sr\n", x, y, si.p.x,
               si.p.y, si.p.z, peak);
  return {stem + "_guide.exr", stem + "_guide.png"};
}

}  // namespace lb
