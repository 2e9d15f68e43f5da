#include "core/bsdfs/plastic.h"
#include <map>
#include <mutex>
#include <tuple>
#include <vector>
#include "core/bsdfs/fresnel.h"
#include "core/sampling.h"

namespace lb {

float fresnelDiffuseReflectance(float eta) {
  if (eta < 1) return -1.4399f * eta * eta + 0.7099f * eta + 0.6681f + 0.0636f / eta;
  float x = 1 / eta;
  return 0.919317f + x * (-3.4793f + x * (6.75335f + x * (-7.80989f + x * (4.98554f + x * -1.36881f))));
}

namespace {

// Gauss–Legendre nodes and weights on [0, 1] (Newton's method on P_n; Press
// et al., Numerical Recipes §4.6).
struct Quadrature {
  std::vector<double> x, w;
};
Quadrature gaussLegendre01(int n) {
  Quadrature q{std::vector<double>(size_t(n)), std::vector<double>(size_t(n))};
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(Pi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1, p1 = 0;
      for (int j = 0; j < n; ++j) {
        double p2 = p1;
        p1 = p0;
        p0 = ((2 * j + 1) * z * p1 - j * p2) / (j + 1);
      }
      dp = n * (z * p0 - p1) / (z * z - 1);
      double step = p0 / dp;
      z -= step;
      if (std::abs(step) < 1e-15) break;
    }
    double w = 2 / ((1 - z * z) * dp * dp);
    q.x[size_t(i)] = (1 - z) / 2, q.x[size_t(n - 1 - i)] = (1 + z) / 2;
    q.w[size_t(i)] = q.w[size_t(n - 1 - i)] = w / 2;
  }
  return q;
}

// The rough coating seen from a direction at cos θ = μ on an interface of
// relative index eta (below 1: from inside), as Mitsuba 3 integrates it
// (render/microfacet.h, eval_reflectance and eval_transmittance): over the
// normals m the distribution shows that direction, the reflected share
// F(wi·m)·G1(wo_r, m) and the refracted share (1 − F(wi·m))·G1(wo_t, m),
// what leaves toward the base (single scattering: light the microsurface
// masks is lost). Taken in the microfacet sampler's own unit square with an
// n × n Gauss rule, weighted by the visible-normal density over the sampler's.
struct CoatingShares {
  double reflected = 0, transmitted = 0;
};
CoatingShares coatingShares(const Microfacet& mf, double mu, float eta, const Quadrature& q) {
  Vec3 wi(float(std::sqrt(std::max(0.0, 1 - mu * mu))), 0.f, float(mu));
  CoatingShares out;
  for (size_t a = 0; a < q.x.size(); ++a)
    for (size_t b = 0; b < q.x.size(); ++b) {
      Vec3 m = mf.sampleNormal(wi, Vec2(float(q.x[a]), float(q.x[b])));
      float cosIM = glm::dot(wi, m);
      double pdf = mf.pdfNormal(wi, m);
      if (cosIM <= 0 || !(pdf > 0)) continue;
      // D_wi(m) = G1(wi) D(m) (wi·m) / cos θi (Heitz 2014, Eq. 2), over the sampler's density.
      double visible = double(mf.G1(wi)) * mf.D(m) * cosIM / mu / pdf;
      double w = q.w[a] * q.w[b] * visible;
      float F = fresnelDielectric(cosIM, eta);
      Vec3 wr = reflect(wi, m), wt;
      if (wr.z > 0) out.reflected += w * F * mf.G1(wr);
      float etap;
      if (F < 1 && refract(wi, m, eta, &etap, &wt) && wt.z < 0) out.transmitted += w * (1 - F) * mf.G1(wt);
    }
  return out;
}

struct RoughTables {
  std::array<float, Plastic::TableSize> transmittance;
  float internalReflectance;
};

// Mitsuba 3's roughplastic (src/bsdfs/roughplastic.cpp): T at 64 values of μ
// from 1e-6 to 1, and F_int = 2 · the mean over the same 64 μ of
// R(μ; 1/η) · μ — its own rule for ∫ R 2μ dμ, kept so the two renderers'
// bases agree (an exact integral is about 1.6 % larger).
RoughTables computeRoughTables(const Microfacet& mf, float eta) {
  RoughTables t{};
  Quadrature outside = gaussLegendre01(64), inside = gaussLegendre01(128);
  double internal = 0;
  for (int k = 0; k < Plastic::TableSize; ++k) {
    double mu = std::max(1e-6, double(k) / (Plastic::TableSize - 1));
    t.transmittance[size_t(k)] = float(glm::clamp(coatingShares(mf, mu, eta, outside).transmitted, 0.0, 1.0));
    internal += coatingShares(mf, mu, 1 / eta, inside).reflected * mu;
  }
  t.internalReflectance = float(glm::clamp(2 * internal / Plastic::TableSize, 0.0, 1.0));
  return t;
}

// Scenes repeat a coating with many base colours: tabulate each once.
const RoughTables& roughTables(const Microfacet& mf, float eta) {
  static std::mutex mutex;
  static std::map<std::tuple<float, float, int, int>, RoughTables> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto key = std::make_tuple(mf.alpha(), eta, int(mf.kind()), int(mf.masking()));
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, computeRoughTables(mf, eta)).first;
  return it->second;
}

float mean(const Color& c) { return (c.r + c.g + c.b) / 3; }
Vec3 upper(const Vec3& w) { return {w.x, w.y, std::abs(w.z)}; }
Vec3 onSideOf(const Vec3& w, const Vec3& side) { return side.z < 0 ? Vec3(w.x, w.y, -w.z) : w; }

}  // namespace

Plastic::Plastic(const PlasticParams& params)
    : params_(params), mf_(std::max(params.alpha, 1e-4f), params.kind, params.masking) {
  float s = mean(params.specular), d = mean(params.diffuseMean);
  specularWeight_ = s + d > 0 ? s / (s + d) : 0.5f;
  if (smooth()) {
    internalReflectance_ = fresnelDiffuseReflectance(1 / params.eta);
  } else {
    const RoughTables& t = roughTables(mf_, params.eta);
    transmittance_ = t.transmittance;
    internalReflectance_ = t.internalReflectance;
  }
}

float Plastic::transmittance(float mu) const {
  mu = glm::clamp(mu, 0.f, 1.f);
  if (smooth()) return 1 - fresnelDielectric(mu, params_.eta);
  float x = mu * (TableSize - 1);
  int i = std::min(int(x), TableSize - 2);
  float t = x - float(i);
  return (1 - t) * transmittance_[size_t(i)] + t * transmittance_[size_t(i + 1)];
}

float Plastic::coatProbability(float muO) const {
  float reflected = 1 - transmittance(muO);
  float coat = reflected * specularWeight_, base = (1 - reflected) * (1 - specularWeight_);
  return coat + base > 0 ? coat / (coat + base) : 0.f;
}

Color Plastic::baseF(float muO, float muI, const Color& texture) const {
  Color rho = params_.diffuse * texture;
  Color inter = params_.nonlinear ? Color(1.f) - rho * internalReflectance_ : Color(1 - internalReflectance_);
  return rho / inter * (InvPi / sqr(params_.eta) * transmittance(muO) * transmittance(muI));
}

Color Plastic::coatF(const Vec3& wo, const Vec3& wi) const {
  Vec3 h = glm::normalize(wo + wi);
  float F = fresnelDielectric(glm::dot(wo, h), params_.eta);
  return params_.specular * (mf_.D(h) * F * mf_.G(wo, wi) / (4 * wo.z * wi.z));
}

float Plastic::coatPdf(const Vec3& wo, const Vec3& wi) const {
  Vec3 h = glm::normalize(wo + wi);
  float cosOH = glm::dot(wo, h);
  return cosOH > 0 ? mf_.pdfNormal(wo, h) / (4 * cosOH) : 0.f;
}

BSDFEval Plastic::evalTextured(const Vec3& wo, const Vec3& wi, TransportMode, const Color& texture) const {
  if (wo.z == 0 || wi.z == 0 || !sameHemisphere(wo, wi)) return {};
  Vec3 o = upper(wo), i = upper(wi);
  Color f = baseF(o.z, i.z, texture);
  if (!smooth()) f += coatF(o, i);
  return {f, pdf(wo, wi), pdf(wi, wo)};
}

float Plastic::pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z == 0 || wi.z == 0 || !sameHemisphere(wo, wi)) return 0;
  Vec3 o = upper(wo), i = upper(wi);
  float coat = coatProbability(o.z);
  float p = (1 - coat) * i.z * InvPi;
  if (!smooth()) p += coat * coatPdf(o, i);
  return p;
}

std::optional<BSDFSample> Plastic::sampleTextured(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode,
                                                  const Color& texture) const {
  if (wo.z == 0) return std::nullopt;
  Vec3 o = upper(wo);
  float coat = coatProbability(o.z);
  Vec3 i;
  uint32_t lobe;
  if (uLobe < coat) {
    if (smooth()) {  // the delta mirror: f·cos/pdf = specular·F / P(coat)
      Vec3 wi = onSideOf(Vec3(-o.x, -o.y, o.z), wo);
      Color f = params_.specular * (fresnelDielectric(o.z, params_.eta) / o.z);
      return BSDFSample{wi, f, coat, coat, BSDFReflection | BSDFSpecular};
    }
    Vec3 m = mf_.sampleNormal(o, u);
    if (glm::dot(o, m) <= 0) return std::nullopt;  // a back-facing normal (Beckmann samples all of D)
    i = reflect(o, m);
    lobe = BSDFReflection | BSDFGlossy;
  } else {
    i = sampleCosineHemisphere(u);
    lobe = BSDFReflection | BSDFDiffuse;
  }
  if (i.z <= 0) return std::nullopt;
  Vec3 wi = onSideOf(i, wo);
  BSDFEval e = evalTextured(wo, wi, mode, texture);
  if (e.pdf == 0) return std::nullopt;
  return BSDFSample{wi, e.f, e.pdf, e.pdfRev, lobe};
}

}  // namespace lb
