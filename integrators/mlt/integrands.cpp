#include "integrators/mlt/integrands.h"
#include "integrators/bidirectional/subpaths.h"
#include <algorithm>

namespace lb::mlt {

namespace {
// The image, and the margin a pixel filter wider than a pixel reaches past
// its edge (core/filter.h), uniformly: Mlt::renderPass scales by its area.
Vec2 rasterFrom(const Scene& scene, Vec2 u) {
  float m = scene.camera.filter().margin();
  if (m == 0) return {u.x * float(scene.camera.width()), u.y * float(scene.camera.height())};
  return {u.x * (float(scene.camera.width()) + 2 * m) - m, u.y * (float(scene.camera.height()) + 2 * m) - m};
}
}  // namespace

void PathIntegrand::evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const {
  PrimarySampleStream sampler(u, 0);
  Vec2 raster = rasterFrom(scene_, sampler.get2D());
  Color L = estimator_.Li(scene_.camera.generateRay(raster), scene_, sampler, rays);
  if (!isBlack(L)) out.push_back({raster, L});
}

void BdptIntegrand::evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const {
  PrimarySampleStream camera(u, 0), light(u, 1), connection(u, 2);
  thread_local bidir::SubpathBuffers buffers;
  buffers.fit(length_);
  Vec2 raster = rasterFrom(scene_, camera.get2D());
  bidir::sampleAllStrategies(scene_, {camera, light, connection}, length_, mis_, raster, buffers, rays,
                             [&](int, int t, const bidir::Connection& c) {
                               out.push_back({t == 1 ? c.raster : raster, c.L * c.weight});
                             });
}

MultiplexedIntegrand::MultiplexedIntegrand(const Scene& scene, int maxSegments, bidir::MisWeighting mis)
    : scene_(scene), maxSegments_(maxSegments), mis_(mis) {
  setLengthProbabilities(std::vector<double>(size_t(maxSegments), 1.0));
}

void MultiplexedIntegrand::setLengthProbabilities(const std::vector<double>& p) {
  double total = 0;
  for (double x : p) total += x;
  lengthPmf_.clear(), lengthCdf_.clear();
  double running = 0;
  for (double x : p) {
    lengthPmf_.push_back(float(x / total));
    running += x / total;
    lengthCdf_.push_back(float(running));
  }
  lengthCdf_.back() = 1;
}

MultiplexedIntegrand::Choice MultiplexedIntegrand::choose(float uLength, float uStrategy) const {
  int index = int(std::upper_bound(lengthCdf_.begin(), lengthCdf_.end(), uLength) - lengthCdf_.begin());
  index = std::min(index, maxSegments_ - 1);
  int k = index + 1;
  int n = strategies(k);
  int s = std::min(int(uStrategy * float(n)), n - 1);
  // The probability the float CDF actually gives this length.
  float pLength = lengthCdf_[size_t(index)] - (index > 0 ? lengthCdf_[size_t(index - 1)] : 0.f);
  return {k, s, k + 1 - s, pLength / float(n)};
}

void MultiplexedIntegrand::evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const {
  PrimarySampleStream control(u, Control), camera(u, Camera), light(u, Light), connection(u, Connection);
  Vec2 c = control.get2D();
  Choice choice = choose(c.x, c.y);
  // Subpaths of exactly t and s vertices (shorter if a walk ends early, and
  // then the strategy has nothing to connect). Russian roulette would only
  // add noise to a walk whose length is already chosen: off.
  PathLength length{choice.k, false, 0};
  thread_local std::vector<bidir::Vertex> cameraPath, lightPath;
  cameraPath.resize(size_t(choice.t));
  lightPath.resize(size_t(std::max(choice.s, 1)));
  Vec2 raster = rasterFrom(scene_, camera.get2D());
  if (bidir::generateCameraSubpath(scene_, camera, length, raster, cameraPath, rays) < choice.t) return;
  // s = 1 samples its light point in connect(); s = 0 needs none.
  if (choice.s >= 2 && bidir::generateLightSubpath(scene_, light, length, lightPath, rays) < choice.s) return;
  bidir::computePartialSums(scene_, mis_, {}, cameraPath, choice.t, bidir::SubpathSide::Camera);
  if (choice.s >= 2) bidir::computePartialSums(scene_, mis_, {}, lightPath, choice.s, bidir::SubpathSide::Light);
  bidir::Connection con = bidir::connect(scene_, connection, mis_, lightPath, cameraPath, choice.s, choice.t, rays);
  if (isBlack(con.L) || con.weight == 0) return;
  out.push_back({choice.t == 1 ? con.raster : raster, con.L * (con.weight / choice.probability)});
}

std::vector<double> lengthContributions(const MultiplexedIntegrand& integrand, const SmallStep& step, uint64_t seed,
                                        uint64_t n, uint64_t& rays) {
  std::vector<float> f(n, 0.f);
  std::vector<int> length(n, 1);
  forEachBootstrapSample(integrand, step, hashValues(seed, 0x9170), n, rays,
                         [&](uint64_t i, PrimarySampleVector& u, const std::vector<Contribution>& c) {
                           // Reading the control numbers again returns the values just used.
                           length[i] = integrand.choose(u.get(MultiplexedIntegrand::Control, 0),
                                                        u.get(MultiplexedIntegrand::Control, 1)).k;
                           f[i] = targetValue(c);
                         });
  size_t K = integrand.lengthProbabilities().size();
  std::vector<double> sum(K, 0.0);
  for (uint64_t i = 0; i < n; ++i) sum[size_t(length[i] - 1)] += double(f[i]);  // index order: deterministic
  for (double& x : sum) x /= double(n);
  return sum;
}

}  // namespace lb::mlt
