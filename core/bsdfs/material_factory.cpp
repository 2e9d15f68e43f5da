#include "core/bsdfs/material_factory.h"
#include "core/bsdfs/conductor.h"
#include "core/bsdfs/layered.h"
#include "core/bsdfs/dielectric.h"
#include "core/bsdfs/diffuse.h"
#include "core/bsdfs/named_conductors.h"
#include "core/bsdfs/plastic.h"
#include "core/bsdfs/rough_diffuse.h"
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
// Smith's masking: height-correlated (pbrt-v4's, the default) or separable
// (Mitsuba's; core/bsdfs/microfacet.h).
Masking masking(Params& p) {
  return p.getChoice("masking", "height_correlated", {"height_correlated", "separable"}) == "separable"
             ? Masking::Separable : Masking::HeightCorrelated;
}
float ior(Params& p, float fallback) {
  float v = p.getFloat("ior", fallback);
  if (!(v > 0)) p.fail("ior", "must be positive");
  return v;
}
// `normal_map` (a texture read as linear RGB: give `srgb: false` to an
// image), or `bump_map` with `bump_scale`, and `opacity` (a number in [0, 1]
// or a texture); core/textures/surface_maps.h says what each does.
Material::SurfaceMaps surfaceMaps(Params& p, const std::string& folder) {
  Material::SurfaceMaps maps;
  if (auto tp = p.getChild("normal_map")) maps.normal = makeTexture(*tp, folder);
  if (auto tp = p.getChild("bump_map")) {
    if (maps.normal) p.fail("bump_map", "a material takes a normal_map or a bump_map, not both");
    maps.bump = makeTexture(*tp, folder);
    maps.bumpScale = p.getFloat("bump_scale", 1.f);
    if (!std::isfinite(maps.bumpScale)) p.fail("bump_scale", "must be finite");
  } else if (p.has("bump_scale")) {
    p.fail("bump_scale", "needs a bump_map");
  }
  if (p.node()["opacity"] && p.node()["opacity"].IsMap()) {
    Params tp = *p.getChild("opacity");
    maps.opacity = makeTexture(tp, folder);
  } else if (p.has("opacity")) {
    float a = p.getFloat("opacity", 1.f);
    if (!(a >= 0 && a <= 1)) p.fail("opacity", "must be in [0, 1]");
    if (a < 1) maps.opacity = std::make_shared<CheckerboardTexture>(Color(a), Color(a), std::array<float, 6>{1, 0, 0, 0, 1, 0});
  }
  return maps;
}

}  // namespace

std::unique_ptr<Material> makeMaterial(Params& p, const std::string& folder) {
  std::string type =
      p.getChoice("type", "diffuse", {"diffuse", "rough_diffuse", "conductor", "dielectric", "thin_dielectric", "plastic",
                                      "coated_diffuse", "coated_conductor"});
  // A texture scales f (material.h): the albedo of a diffuse or plastic
  // surface (plastic's diffuse base only), the tint of a conductor. Elsewhere
  // f is not linear in a colour we could texture.
  const char* texturedKey = type == "conductor" || type == "coated_conductor" ? "tint" : "albedo";
  std::shared_ptr<const Texture> texture;
  if (auto tp = p.getChild("texture")) {
    if (type == "dielectric" || type == "thin_dielectric")
      p.fail("texture", "only diffuse, rough_diffuse, plastic, conductor and coated materials take a texture");
    texture = makeTexture(*tp, folder);
    Color base = p.getColor(texturedKey, Color(type == "conductor" || type == "coated_conductor" ? 1.f : 0.5f));
    if (glm::any(glm::greaterThan(texture->maxValue() * base, Color(1.f))))
      p.fail("texture", "its values times the material's " + std::string(texturedKey) + " exceed 1 (energy conservation)");
  }
  std::unique_ptr<Material> m;
  if (type == "diffuse") {
    m = std::make_unique<Diffuse>(reflectance(p, "albedo", Color(0.5f)));
  } else if (type == "rough_diffuse") {
    Color albedo = reflectance(p, "albedo", Color(0.5f));
    float r = p.getFloat("roughness", 0.2f);
    if (!(r >= 0)) p.fail("roughness", "must not be negative");
    m = std::make_unique<RoughDiffuse>(albedo, r, p.getBool("fast_approximation", false));
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
    Masking mask = masking(p);
    if (alpha < SmoothAlpha) m = std::make_unique<SmoothConductor>(fresnel);
    else m = std::make_unique<RoughConductor>(fresnel, alpha, kind, mask);
  } else if (type == "thin_dielectric") {
    m = std::make_unique<ThinDielectric>(ior(p, 1.5f));
  } else if (type == "coated_diffuse" || type == "coated_conductor") {
    // pbrt-v4's coateddiffuse and coatedconductor (core/bsdfs/layered.h).
    LayeredParams lp;
    lp.eta = ior(p, 1.5f);
    float alpha = roughness(p);
    lp.alpha = alpha < SmoothAlpha ? 0.f : alpha;
    lp.kind = distribution(p);
    lp.thickness = p.getFloat("thickness", 0.01f);
    if (!(lp.thickness >= 0) || !std::isfinite(lp.thickness)) p.fail("thickness", "must be a finite number >= 0");
    lp.maxDepth = p.getInt("max_depth", 10);
    if (lp.maxDepth < 1 || lp.maxDepth > 1000) p.fail("max_depth", "must be in [1, 1000]");
    lp.samples = p.getInt("samples", 1);
    if (lp.samples < 1 || lp.samples > 1000) p.fail("samples", "must be in [1, 1000]");
    std::unique_ptr<Material> base;
    if (type == "coated_diffuse") {
      base = std::make_unique<Diffuse>(reflectance(p, "albedo", Color(0.5f)));
    } else {
      ConductorFresnel fresnel;
      fresnel.tint = reflectance(p, "tint", Color(1.f));
      fresnel.complexIor = true;
      const ComplexIor& copper = *namedConductor("Cu");  // pbrt-v4's default conductor
      fresnel.eta = p.getColor("conductor_eta", Color(copper.eta));
      fresnel.k = p.getColor("conductor_k", Color(copper.k));
      if (glm::any(glm::lessThanEqual(fresnel.eta, Color(0.f)))) p.fail("conductor_eta", "must be positive");
      if (glm::any(glm::lessThan(fresnel.k, Color(0.f)))) p.fail("conductor_k", "must not be negative");
      // The metal lies under the coating: its Fresnel sees the index relative
      // to the coating's (pbrt-v4's CoatedConductorMaterial divides likewise).
      fresnel.eta /= lp.eta;
      fresnel.k /= lp.eta;
      float a = p.getFloat("conductor_roughness", 0.f);
      if (!(a >= 0 && a <= 1)) p.fail("conductor_roughness", "must be in [0, 1]");
      if (a < SmoothAlpha) base = std::make_unique<SmoothConductor>(fresnel);
      else base = std::make_unique<RoughConductor>(fresnel, a, lp.kind);
    }
    m = std::make_unique<Layered>(lp, std::move(base));
  } else if (type == "plastic") {
    PlasticParams pp;
    pp.diffuse = reflectance(p, "albedo", Color(0.5f));
    pp.diffuseMean = texture ? pp.diffuse * texture->mean() : pp.diffuse;
    pp.specular = reflectance(p, "specular", Color(1.f));
    pp.eta = ior(p, 1.49f);
    float alpha = roughness(p);
    pp.alpha = alpha < SmoothAlpha ? 0.f : alpha;
    pp.kind = distribution(p);
    pp.masking = masking(p);
    pp.nonlinear = p.getBool("nonlinear", false);
    m = std::make_unique<Plastic>(pp);
  } else {
    float eta = ior(p, 1.5f);
    float alpha = roughness(p);
    MicrofacetKind kind = distribution(p);
    Masking mask = masking(p);
    // An index-matched interface does not bend light: rough or not, it is a
    // straight pass-through, which only the smooth model represents.
    if (alpha < SmoothAlpha || eta == 1.f) m = std::make_unique<SmoothDielectric>(eta);
    else m = std::make_unique<RoughDielectric>(eta, alpha, kind, mask);
  }
  if (texture) m->setTexture(std::move(texture));
  m->setSurfaceMaps(surfaceMaps(p, folder));
  p.checkUnused();
  return m;
}

}  // namespace lb
