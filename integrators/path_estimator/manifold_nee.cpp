// Connections through glass in the path tracer: manifold next-event
// estimation (mnee; Hanika, Droske & Fascione 2015) and specular manifold
// sampling (sms; Zeltner, Georgiev & Jakob 2020). At a non-delta vertex x_0 a
// light point y, sampled by area, is connected through smooth refracting
// surfaces by the solver of integrators/manifold/specular_chain.h.
//
// The estimate of one chain (the paper's Eq. 7 in our measure;
// specular_chain.h derives it)
//     β f(ω_0) |cos θ_0^s| / |cos θ_0^g| · T · E_y · |dω_y/dA_0| / (P(light) p_A(y)),
// with E_y = L_e(y → x_k) |cos θ_y| for an area light and the intensity
// I(y → x_k) for a point or spot light, counts if x_k → y is unoccluded.
//  * mnee: the chain Newton's method reaches from the straight segment
//    x_0 → y (1 … mnee_max_chain surfaces). Several solutions: one is found.
//  * sms: unbiased (Zeltner et al. §4.2–4.3): Newton's method from a seed
//    drawn uniformly by area on the scene's smooth dielectrics finds solution
//    s with some probability p_s; its estimate is divided by p_s, which is
//    estimated without bias by the number N of further seeds drawn until one
//    reaches s again (geometric, E[N] = 1/p_s), at most sms_trials (a
//    solution with p_s well below 1/sms_trials is undercounted: the
//    truncation's bias). Over the seeds, Σ_s p_s · c_s / p_s: every solution
//    a seed can reach, each once.
//  * sms: biased (their §4.4): sms_trials seeds, the distinct solutions they
//    reach each counted once (a solution no seed reached is lost).
// sms seeds chains of one or two surfaces (a water surface; into and out of
// a sphere; a mirror): the seed's ray from x_0, refracted or reflected on
// while it meets glass or mirrors.
// Neither is weighted against another strategy: the paths they find (a
// non-delta vertex, then 1 … max_chain delta refractions — or, for sms,
// mirror reflections — then an area light)
// are theirs alone, and where BSDF sampling reaches such a light it counts
// zero (shadeVertex's manifoldCovers; manifoldChainAfter counts the chain).
// Infinite lights are left to ordinary next-event estimation and BSDF
// sampling (a direction, not a point, would be solved for).
#include <algorithm>
#include "core/bsdfs/conductor.h"
#include "core/bsdfs/dielectric.h"
#include "core/bsdfs/fresnel.h"
#include "integrators/manifold/reciprocal_probability.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb {
namespace {

// The estimate of one chain to the light point `e` (as above, without β),
// and the shadow ray from its last vertex; black if it carries nothing.
Color chainEstimate(const SurfaceInteraction& si, const BSDF& bsdf, const ManifoldConnection& chain,
                    const Light& light, float pmf, const LightEmission& e, Ray* shadow) {
  const SurfaceInteraction& last = chain.vertices[chain.k - 1];
  Vec3 toLight = e.p - last.p;
  float distance = glm::length(toLight);
  Color emitted;
  if (light.isDelta()) {
    auto li = light.sampleLi(last.p, 0.5f, Vec2(0.5f));  // I / r² towards x_k
    if (!li) return Color(0.f);
    emitted = li->L * sqr(distance);
  } else {
    emitted = light.L(e.n, -toLight / distance) * absDot(e.n, toLight / distance);
  }
  Color f = bsdf.eval(si.wo, chain.wi, TransportMode::Radiance).f;
  float cosGeometric = absDot(chain.wi, si.ng);
  if (isBlack(f) || isBlack(emitted) || !(cosGeometric > 0)) return Color(0.f);
  float cosRatio = absDot(chain.wi, bsdf.shadingNormal()) / cosGeometric;
  *shadow = last.spawnRayTo(e.p, e.pError, e.n);
  return f * cosRatio * chain.throughput * emitted * float(chain.geometry) / (pmf * e.pdfPos);
}

// Whether two chains are the same solution.
bool sameSolution(const ManifoldConnection& a, const ManifoldConnection& b) {
  if (a.k != b.k) return false;
  for (int i = 0; i < a.k; ++i)
    if (a.vertices[i].shapeId != b.vertices[i].shapeId ||
        !(glm::length(a.vertices[i].p - b.vertices[i].p) < 1e-4f * (1 + glm::length(a.vertices[i].p))))
      return false;
  return true;
}

}  // namespace

void PathEstimator::prepareSmsCasters(const Scene& scene) {
  std::vector<float> areas;
  for (size_t i = 0; i < scene.shapes().size(); ++i) {
    const Shape& shape = scene.shapes()[i];
    if (shape.materialId < 0 || !shape.triangleMaterials.empty()) continue;
    const Material& material = scene.material(shape.materialId);
    bool specular = dynamic_cast<const SmoothDielectric*>(&material) || dynamic_cast<const SmoothConductor*>(&material);
    if (!specular || material.perturbsShading()) continue;
    smsCasters_.push_back(int(i));
    areas.push_back(shape.area());
  }
  if (!areas.empty()) smsCasterAreas_ = DiscreteDistribution(areas);
}

std::optional<ManifoldConnection> PathEstimator::smsTrial(const Scene& scene, const SurfaceInteraction& si,
                                                          const Vec3& y, Pcg32& rng) const {
  size_t caster = smsCasterAreas_.sample(rng.next1D());
  float uPick = rng.next1D();
  Vec2 u(rng.next1D(), rng.next1D());
  ShapeSample seed = scene.shapes()[size_t(smsCasters_[caster])].sampleArea(uPick, u);
  // The seed as a chain vertex: where the ray from x_0 towards it meets the
  // glass or mirror (Newton's projections trace from x_0 too); then the
  // chain the ray goes on to, refracted or reflected at each vertex, while it
  // meets glass or mirrors and the chain has room (Zeltner et al. §5: the
  // seed path; two vertices through a sphere).
  SurfaceInteraction hits[ManifoldConnection::MaxChain];
  if (!scene.intersect(si.spawnRay(glm::normalize(seed.p - si.p)), hits[0]) || !isSpecularChainSurface(scene, hits[0]))
    return std::nullopt;
  int k = 1;
  while (k < settings_.manifold.maxChain) {
    const SurfaceInteraction& v = hits[k - 1];
    Vec3 next;
    float etap;
    if (const auto* glass = dynamic_cast<const SmoothDielectric*>(v.material)) {
      if (!refract(v.wo, v.shading.n, glass->eta(), &etap, &next)) break;
    } else {
      next = reflect(v.wo, v.shading.n);
    }
    if (!scene.intersect(v.spawnRay(next), hits[k]) || !isSpecularChainSurface(scene, hits[k])) break;
    ++k;
  }
  return solveSpecularChain(scene, si, y, hits, k, settings_.manifold);
}

bool PathEstimator::manifoldLightSample(const PathState& s, const SurfaceInteraction& si, const BSDF& bsdf,
                                        const PathContext& c, uint32_t slot, ShadowRequest& out) const {
  c.sampler.setDimension(slot);
  float pmf = 0;
  const Light* light = chooseLight(c.scene, si.p, c.sampler.get1D(), &pmf);
  float uPick = c.sampler.get1D();
  Vec2 uPos = c.sampler.get2D();
  if (!light || light->isInfinite() || !(pmf > 0)) return false;
  // A point by area (sampleLe's position; its direction is not used, and
  // uDir.x < 1/2 keeps a two-sided light's front, whose L() is both sides').
  auto e = light->sampleLe(uPick, uPos, Vec2(0.25f, 0.5f));
  if (!e || !(e->pdfPos > 0)) return false;
  // The chain's path has the vertex's segments, k more, and the one to the light.
  auto fits = [&](const ManifoldConnection& chain) { return s.vertex + 1 + chain.k + 1 <= c.maxDepth; };
  out.unweighted = 0;
  out.tested = false;
  if (settings_.mnee) {
    auto chain = connectThroughSpecularChain(c.scene, si, e->p, settings_.manifold);
    if (!chain || !fits(*chain)) return false;
    Color estimate = chainEstimate(si, bsdf, *chain, *light, pmf, *e, &out.ray);
    if (isBlack(estimate)) return false;
    out.contribution = s.beta * estimate;
    out.segments = s.vertex + 1 + chain->k + 1;
    return true;
  }
  if (smsCasters_.empty()) return false;
  // The seeds draw from a generator of their own, keyed by one sampler number:
  // their count varies, the sampler's dimensions may not.
  Pcg32 rng(hashValues(uint64_t(c.sampler.get1D() * 0x1p24f), slot), 0x5e3d5);
  if (settings_.sms == SmsMode::Unbiased) {
    auto chain = smsTrial(c.scene, si, e->p, rng);
    if (!chain || !fits(*chain)) return false;
    Color estimate = chainEstimate(si, bsdf, *chain, *light, pmf, *e, &out.ray);
    if (isBlack(estimate)) return false;
    // Seeds until one reaches this solution again: E[n] = 1/p.
    int n = trialsUntilSuccess(
        [&] {
          auto again = smsTrial(c.scene, si, e->p, rng);
          return again && sameSolution(*again, *chain);
        },
        settings_.smsTrials);
    out.contribution = s.beta * estimate * float(n);
    out.segments = s.vertex + 1 + chain->k + 1;
    return true;
  }
  // Biased: the distinct solutions of sms_trials seeds, each tested for
  // visibility here and summed into one request.
  constexpr int MaxSolutions = 8;
  ManifoldConnection found[MaxSolutions];
  int count = 0;
  Color sum(0.f);
  for (int trial = 0; trial < settings_.smsTrials; ++trial) {
    auto chain = smsTrial(c.scene, si, e->p, rng);
    if (!chain || !fits(*chain)) continue;
    if (std::any_of(found, found + count, [&](const ManifoldConnection& f) { return sameSolution(f, *chain); }))
      continue;
    if (count == MaxSolutions) break;
    found[count++] = *chain;
    Ray shadow;
    Color estimate = chainEstimate(si, bsdf, *chain, *light, pmf, *e, &shadow);
    if (!isBlack(estimate) && !c.scene.occluded(shadow)) sum += estimate;
  }
  if (isBlack(sum)) return false;
  out.contribution = s.beta * sum;
  out.segments = s.vertex + 1 + found[0].k + 1;
  out.tested = true;
  return true;
}

// After scattering at a vertex with `bsdf`: 0 from a non-delta vertex (where
// a manifold connection was made), one more after a refraction through smooth
// glass or (sms) a reflection off a smooth mirror, else −1 (the light that
// path reaches is not a manifold connection's).
int PathEstimator::manifoldChainAfter(int chain, const BSDF& bsdf, bool refracted, bool reflected) const {
  if (!bsdf.isDelta()) return 0;
  bool glass = refracted && dynamic_cast<const SmoothDielectric*>(&bsdf.material()) != nullptr;
  bool mirror = reflected && settings_.sms != SmsMode::Off &&
                dynamic_cast<const SmoothConductor*>(&bsdf.material()) != nullptr;
  return (glass || mirror) && chain >= 0 && chain < settings_.manifold.maxChain ? chain + 1 : -1;
}

}  // namespace lb
