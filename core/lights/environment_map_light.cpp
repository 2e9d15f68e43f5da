#include "core/lights/environment_map_light.h"
#include <algorithm>
#include <cmath>
#include "core/lights/environment_light.h"

namespace lb {

EnvironmentMapLight::EnvironmentMapLight(Image map, float scale, const Mat3& toWorld, bool importance)
    : map_(std::move(map)), scale_(scale), toWorld_(toWorld), toMap_(glm::transpose(toWorld)), importance_(importance) {
  // The weights are relative: divided by the brightest texel, so that a row's
  // sum stays a float for any map whose texels are (a wide map of 1e35s
  // summed past 3.4e38 and gave NaN probabilities: issue 34, class 1).
  float brightest = 0;
  for (const Color& c : map_.pixels) brightest = std::max({brightest, c.r, c.g, c.b});
  unit_ = brightest > 0 ? 1.0 / double(brightest) : 1.0;
  rowSinTheta_.resize(size_t(map_.height));
  for (int y = 0; y < map_.height; ++y) rowSinTheta_[size_t(y)] = std::sin(Pi * (y + 0.5) / map_.height);
  full_ = texelDistribution([&](int x, int y) { return relativeMax(x, y) * rowSinTheta_[size_t(y)]; });
}

double EnvironmentMapLight::relativeMax(int x, int y) const {
  const Color& c = map_.at(x, y);
  return double(std::max({c.r, c.g, c.b})) * unit_;
}

// Built on first use, once (path tracing with mis_compensation is the only
// user: no other estimator pays its memory or time).
const EnvironmentMapLight::TexelDistribution& EnvironmentMapLight::distribution(bool compensated) const {
  if (!compensated) return full_;
  std::call_once(compensatedOnce_, [this] {
    // The mean of m over the sphere, in the measure the distribution itself
    // uses (sin θ at texel centres). A texel within a millionth of the mean
    // counts as at it: a constant map's rounding must not become a distribution.
    double weighted = 0, area = 0;
    for (int y = 0; y < map_.height; ++y)
      for (int x = 0; x < map_.width; ++x)
        weighted += relativeMax(x, y) * rowSinTheta_[size_t(y)], area += rowSinTheta_[size_t(y)];
    const double mean = area > 0 ? weighted / area : 0;
    compensated_ = texelDistribution([&](int x, int y) {
      double above = relativeMax(x, y) - mean;
      return above > 1e-6 * mean ? above * rowSinTheta_[size_t(y)] : 0.0;
    });
    compensatedIsFull_ = !(compensated_.rows.total() > 0);
    if (compensatedIsFull_) compensated_ = {};
  });
  return compensatedIsFull_ ? full_ : compensated_;
}

template <typename Weight>
EnvironmentMapLight::TexelDistribution EnvironmentMapLight::texelDistribution(Weight&& weight) const {
  const int w = map_.width, h = map_.height;
  TexelDistribution d;
  std::vector<float> rowWeights(static_cast<size_t>(h));
  d.columns.reserve(size_t(h));
  for (int y = 0; y < h; ++y) {
    std::vector<float> weights(static_cast<size_t>(w));
    double rowSum = 0;
    for (int x = 0; x < w; ++x) {
      weights[size_t(x)] = float(weight(x, y));
      rowSum += weights[size_t(x)];
    }
    d.columns.emplace_back(weights);
    rowWeights[size_t(y)] = float(rowSum);
  }
  d.rows = DiscreteDistribution(rowWeights);
  return d;
}

void EnvironmentMapLight::preprocess(const Bounds3& b) {
  // An empty scene has zero radius; a unit sphere keeps the emission pdfs finite.
  center_ = b.center();
  radius_ = b.radius() > 0 ? b.radius() : 1.f;
}

// The map's frame is the world's turned by the rotation (orthogonal, so its
// inverse is its transpose and densities over directions are unchanged).
Vec2 EnvironmentMapLight::uvOf(const Vec3& world) const {
  Vec3 d = toMap_ * world;
  float phi = std::atan2(d.x, -d.z);
  if (phi < 0) phi += 2 * Pi;
  float theta = std::acos(glm::clamp(d.y, -1.f, 1.f));
  return {phi * Inv2Pi, theta * InvPi};
}

Vec3 EnvironmentMapLight::directionOf(Vec2 uv) const {
  float phi = 2 * Pi * uv.x, theta = Pi * uv.y;
  float s = std::sin(theta);
  Vec3 d(s * std::sin(phi), std::cos(theta), -s * std::cos(phi));
  return toWorld_ * d;
}

const Color& EnvironmentMapLight::texel(Vec2 uv) const {
  int x = std::clamp(int(uv.x * map_.width), 0, map_.width - 1);
  int y = std::clamp(int(uv.y * map_.height), 0, map_.height - 1);
  return map_.at(x, y);
}

Color EnvironmentMapLight::Le(const Vec3& d) const { return texel(uvOf(d)) * scale_; }

float EnvironmentMapLight::directionPdf(const Vec3& d, bool compensated) const {
  if (!importance_) return uniformSpherePdf();
  const TexelDistribution& dist = distribution(compensated);
  Vec2 uv = uvOf(d);
  float sinTheta = std::sin(Pi * uv.y);
  if (!(sinTheta > 0) || dist.rows.total() <= 0) return 0;
  int x = std::clamp(int(uv.x * map_.width), 0, map_.width - 1);
  int y = std::clamp(int(uv.y * map_.height), 0, map_.height - 1);
  // Density over [0,1]²: the texel's probability over its area 1/(w h).
  float pdfUv = dist.rows.pmf(size_t(y)) * dist.columns[size_t(y)].pmf(size_t(x)) * float(map_.width) * float(map_.height);
  return pdfUv / (2 * Pi * Pi * sinTheta);
}

Vec3 EnvironmentMapLight::sampleDirection(Vec2 u, float* pdf, bool compensated) const {
  if (!importance_) {
    *pdf = uniformSpherePdf();
    return sampleUniformSphere(u);
  }
  *pdf = 0;
  const TexelDistribution& dist = distribution(compensated);
  if (dist.rows.total() <= 0) return Vec3(0.f);
  float pmfRow = 0, pmfColumn = 0, uy = 0, ux = 0;
  size_t y = dist.rows.sample(u.y, &pmfRow, &uy);
  size_t x = dist.columns[y].sample(u.x, &pmfColumn, &ux);
  Vec2 uv((float(x) + ux) / float(map_.width), (float(y) + uy) / float(map_.height));
  float sinTheta = std::sin(Pi * uv.y);
  if (!(sinTheta > 0)) return Vec3(0.f);
  *pdf = pmfRow * pmfColumn * float(map_.width) * float(map_.height) / (2 * Pi * Pi * sinTheta);
  return directionOf(uv);
}

std::optional<LightSample> EnvironmentMapLight::sampleLiFrom(const Vec3& ref, Vec2 u, bool compensated) const {
  float pdf = 0;
  Vec3 wi = sampleDirection(u, &pdf, compensated);
  if (!(pdf > 0)) return std::nullopt;
  return LightSample{Le(wi), wi, pdf, ref + wi * (2 * radius_ + glm::length(ref - center_))};
}

std::optional<LightSample> EnvironmentMapLight::sampleLi(const Vec3& ref, float, Vec2 u) const {
  return sampleLiFrom(ref, u, false);
}

float EnvironmentMapLight::pdfLi(const Vec3&, const Vec3& wi, const Vec3&, const Vec3&) const {
  return directionPdf(wi);
}

std::optional<LightSample> EnvironmentMapLight::sampleLiCompensated(const Vec3& ref, float, Vec2 u) const {
  return sampleLiFrom(ref, u, true);
}

float EnvironmentMapLight::pdfLiCompensated(const Vec3&, const Vec3& wi, const Vec3&, const Vec3&) const {
  return directionPdf(wi, true);
}

std::optional<LightEmission> EnvironmentMapLight::sampleLe(float, Vec2 uPos, Vec2 uDir) const {
  float pdfDir = 0;
  Vec3 w = sampleDirection(uDir, &pdfDir);  // towards the environment
  if (!(pdfDir > 0)) return std::nullopt;
  LightEmission e = emitFromBoundingDisc(center_, radius_, w, uPos);
  e.Le = Le(w);
  e.pdfDir = pdfDir;
  return e;
}

void EnvironmentMapLight::pdfLe(const Vec3&, const Vec3&, const Vec3& dir, float* pdfPos, float* pdfDir) const {
  *pdfPos = 1 / (Pi * radius_ * radius_);
  *pdfDir = directionPdf(-dir);
}

Color EnvironmentMapLight::integral() const {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < map_.height; ++y) {
    // A texel row spans θ from π y / h to π (y + 1) / h: solid angle 2π/w × Δcos θ.
    double solidAngle = 2 * Pi / map_.width * (std::cos(Pi * y / map_.height) - std::cos(Pi * (y + 1) / map_.height));
    for (int x = 0; x < map_.width; ++x) sum += glm::dvec3(map_.at(x, y)) * solidAngle;
  }
  return Color(sum) * scale_;
}

// Power through the disc that emitted rays start on (as the constant environment's).
Color EnvironmentMapLight::power() const { return integral() * Pi * radius_ * radius_; }

}  // namespace lb
