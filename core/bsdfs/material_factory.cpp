#include "core/bsdfs/material_factory.h"
#include "core/bsdfs/conductor.h"
#include "core/bsdfs/dielectric.h"
#include "core/bsdfs/diffuse.h"
#include "core/bsdfs/thin_dielectric.h"

namespace lb {

namespace {
Color reflectance(Params& p, const std::string& key, Color fallback) {
  Color c = p.getColor(key, fallback);
  if (glm::any(glm::lessThan(c, Color(0.f)))) p.fail(key, "must not be negative");
  // Above 1 the material creates energy; we refuse rather than warn, because a
  // furnace test or a converged reference would silently be wrong.
  if (glm::any(glm::greaterThan(c, Color(1.f)))) p.fail(key, "must be at most 1 (energy conservation)");
  return c;
}
// Below this GGX alpha the lobe is narrower than float directions resolve;
// pbrt-v4 (TrowbridgeReitzDistribution::EffectivelySmooth) makes the same call.
constexpr float SmoothAlpha = 1e-3f;

float roughness(Params& p) {
  float r = p.getFloat("roughness", 0.f);
  if (r < 0) p.fail("roughness", "must not be negative");
  if (r > 1) p.fail("roughness", "must be at most 1 (the distribution's alpha)");
  return r;
}
MicrofacetKind distribution(Params& p) {
  return p.getChoice("distribution", "ggx", {"ggx", "beckmann"}) == "ggx" ? MicrofacetKind::GGX : MicrofacetKind::Beckmann;
}
}  // namespace

std::unique_ptr<Material> makeMaterial(Params& p, const std::string& folder) {
  std::string type = p.getChoice("type", "diffuse", {"diffuse", "conductor", "dielectric", "thin_dielectric"});
  std::unique_ptr<Material> m;
  if (type == "diffuse") {
    m = std::make_unique<Diffuse>(reflectance(p, "albedo", Color(0.5f)));
  } else if (type == "conductor") {
    ConductorFresnel fresnel;
    fresnel.tint = reflectance(p, "tint", Color(1.f));
    if (p.has("eta") || p.has("k")) {
      fresnel.complexIor = true;
      fresnel.eta = p.getColor("eta", Color(1.f));
      fresnel.k = p.getColor("k", Color(0.f));
      if (glm::any(glm::lessThanEqual(fresnel.eta, Color(0.f)))) p.fail("eta", "must be positive");
      if (glm::any(glm::lessThan(fresnel.k, Color(0.f)))) p.fail("k", "must not be negative");
    }
    float alpha = roughness(p);
    MicrofacetKind kind = distribution(p);
    if (alpha < SmoothAlpha) m = std::make_unique<SmoothConductor>(fresnel);
    else m = std::make_unique<RoughConductor>(fresnel, alpha, kind);
  } else if (type == "thin_dielectric") {
    float ior = p.getFloat("ior", 1.5f);
    if (ior <= 0) p.fail("ior", "must be positive");
    m = std::make_unique<ThinDielectric>(ior);
  } else {
    float ior = p.getFloat("ior", 1.5f);
    if (ior <= 0) p.fail("ior", "must be positive");
    float alpha = roughness(p);
    MicrofacetKind kind = distribution(p);
    // An index-matched interface does not bend light: rough or not, it is a
    // straight pass-through, which only the smooth model represents.
    if (alpha < SmoothAlpha || ior == 1.f) m = std::make_unique<SmoothDielectric>(ior);
    else m = std::make_unique<RoughDielectric>(ior, alpha, kind);
  }
  // A texture scales f (material.h): the albedo of a diffuse surface, the tint
  // of a conductor. Elsewhere f is not linear in a colour we could texture.
  if (auto tp = p.getChild("texture")) {
    if (type != "diffuse" && type != "conductor") p.fail("texture", "only diffuse and conductor materials take a texture");
    auto texture = makeTexture(*tp, folder);
    Color albedo = type == "diffuse" ? p.getColor("albedo", Color(0.5f)) : p.getColor("tint", Color(1.f));
    if (glm::any(glm::greaterThan(texture->maxValue() * albedo, Color(1.f))))
      p.fail("texture", "its values times the material's " + std::string(type == "diffuse" ? "albedo" : "tint") +
                            " exceed 1 (energy conservation)");
    m->setTexture(std::move(texture));
  }
  p.checkUnused();
  return m;
}

}  // namespace lb
