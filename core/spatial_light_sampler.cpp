#include "core/spatial_light_sampler.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <tbb/parallel_for.h>
#include "core/rng.h"

namespace lb {

namespace {
// Fluence of one light at p: luminance(L)/pdf averaged over stratified sampleLi draws.
float estimateFluence(const Light& light, const Vec3& p, uint64_t seed) {
  constexpr int Samples = 8;
  Pcg32 rng(seed, 7);
  double sum = 0;
  for (int i = 0; i < Samples; ++i) {
    Vec2 u = rng.next2D();
    u.x = (float(i) + u.x) / Samples;  // stratified in the first dimension
    auto ls = light.sampleLi(p, rng.next1D(), u);
    // A point light exactly on a grid vertex gives an infinite value: skip
    // that sample, not the light's whole estimate.
    if (!ls || !(ls->pdf > 0)) continue;
    double value = double(luminance(ls->L)) / ls->pdf;
    if (std::isfinite(value)) sum += value;
  }
  float f = float(sum / Samples);
  return std::isfinite(f) ? f : std::numeric_limits<float>::max();
}
}  // namespace

SpatialLightSampler::SpatialLightSampler(const Scene& scene, uint64_t seed) : lights_(&scene.lights()) {
  const auto& lights = scene.lights();
  if (lights.empty()) return;
  bounds_ = scene.bounds();
  if (bounds_.empty()) bounds_.extend(Vec3(0.f));
  // About 4 M light samples at most: fewer voxels for scenes with many lights.
  double verticesAllowed = 4e6 / (8.0 * double(lights.size()));
  res_ = std::clamp(int(std::cbrt(verticesAllowed)) - 1, 1, 16);
  Vec3 size = bounds_.hi - bounds_.lo;
  float floorSize = 1e-6f * std::max(1e-30f, std::max(size.x, std::max(size.y, size.z)));
  extent_ = glm::max(size, Vec3(floorSize));

  const int n = res_ + 1;
  const size_t L = lights.size();
  std::vector<float> vertexFluence(size_t(n) * n * n * L);
  tbb::parallel_for(0, n * n * n, [&](int g) {
    Vec3 t(float(g % n), float((g / n) % n), float(g / (n * n)));
    Vec3 p = bounds_.lo + extent_ * t / float(res_);
    for (size_t l = 0; l < L; ++l)
      vertexFluence[size_t(g) * L + l] = estimateFluence(*lights[l], p, hashValues(seed, uint64_t(g), l));
  });

  const LightSampler& fallback = scene.lightSampler();
  voxels_.resize(size_t(res_) * res_ * res_);
  tbb::parallel_for(0, res_ * res_ * res_, [&](int v) {
    int x = v % res_, y = (v / res_) % res_, z = v / (res_ * res_);
    std::vector<float> s(L, 0.f);
    for (int c = 0; c < 8; ++c) {
      int g = (x + (c & 1)) + n * ((y + ((c >> 1) & 1)) + n * (z + (c >> 2)));
      for (size_t l = 0; l < L; ++l) s[l] = std::max(s[l], vertexFluence[size_t(g) * L + l]);
    }
    double total = 0;
    for (float w : s) total += w;
    std::vector<float> weights(L);
    for (size_t l = 0; l < L; ++l) {
      float scenePmf = fallback.pmf(lights[l].get());
      float spatial = total > 0 ? float(s[l] / total) : scenePmf;
      // A light the scene never selects (it emits nothing) stays unselected.
      weights[l] = scenePmf > 0 ? (1 - DefensiveFraction) * spatial + DefensiveFraction * scenePmf : 0.f;
    }
    voxels_[size_t(v)] = DiscreteDistribution(weights);
  });
}

size_t SpatialLightSampler::voxelOf(const Vec3& p) const {
  Vec3 t = (p - bounds_.lo) / extent_ * float(res_);
  // Clamped as floats first: a NaN or a huge coordinate (a point-sized scene)
  // must not reach the int conversion.
  auto cell = [&](float c) { return c > 0 ? int(std::min(c, float(res_ - 1))) : 0; };
  return size_t(cell(t.x) + res_ * (cell(t.y) + res_ * cell(t.z)));
}

const Light* SpatialLightSampler::sample(const Vec3& p, float u, float* pmf) const {
  if (voxels_.empty()) return nullptr;
  return (*lights_)[voxels_[voxelOf(p)].sample(u, pmf)].get();
}

float SpatialLightSampler::pmf(const Vec3& p, const Light* light) const {
  if (voxels_.empty()) return 0.f;
  return voxels_[voxelOf(p)].pmf(size_t(light->index));
}

}  // namespace lb
