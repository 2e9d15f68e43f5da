// Manifold next-event estimation in the path tracer (Hanika, Droske &
// Fascione 2015): at a non-delta vertex x_0, a light point y sampled by area
// is connected through the smooth refracting surfaces the straight segment
// x_0 → y crosses, by the solver of integrators/manifold/specular_chain.h.
//
// Its estimate (the paper's Eq. 7 in our measure; specular_chain.h derives it)
//     β f(ω_0) |cos θ_0^s| / |cos θ_0^g| · T · E_y · |dω_y/dA_0| / (P(light) p_A(y)),
// with E_y = L_e(y → x_k) |cos θ_y| for an area light and the intensity
// I(y → x_k) for a point or spot light, counts if x_k → y is unoccluded
// (the shadow request). It is not weighted against another strategy: the
// paths it finds — a non-delta vertex, then 1 … mnee_max_chain delta
// refractions, then an area light — are its alone, and where BSDF sampling
// reaches such a light it counts zero (shadeVertex's manifoldCovers; the
// chain is counted by manifoldChainAfter). Infinite lights are left to
// ordinary next-event estimation and BSDF sampling (a direction, not a
// point, would be solved for).
#include "core/bsdfs/dielectric.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

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
  auto chain = connectThroughSpecularChain(c.scene, si, e->p, settings_.manifold);
  // The chain's path has the vertex's segments, k more, and the one to the light.
  if (!chain || s.vertex + 1 + chain->k + 1 > c.maxDepth) return false;
  const SurfaceInteraction& last = chain->vertices[chain->k - 1];
  Vec3 toLight = e->p - last.p;
  float distance = glm::length(toLight);
  Color emitted;
  if (light->isDelta()) {
    auto li = light->sampleLi(last.p, 0.5f, Vec2(0.5f));  // I / r² towards x_k
    if (!li) return false;
    emitted = li->L * sqr(distance);
  } else {
    emitted = light->L(e->n, -toLight / distance) * absDot(e->n, toLight / distance);
  }
  Color f = bsdf.eval(si.wo, chain->wi, TransportMode::Radiance).f;
  float cosGeometric = absDot(chain->wi, si.ng);
  if (isBlack(f) || isBlack(emitted) || !(cosGeometric > 0)) return false;
  float cosRatio = absDot(chain->wi, bsdf.shadingNormal()) / cosGeometric;
  Color contribution = f * cosRatio * chain->transmittance * emitted * float(chain->geometry) / (pmf * e->pdfPos);
  out.ray = last.spawnRayTo(e->p, e->pError, e->n);
  out.contribution = s.beta * contribution;
  out.unweighted = 0;
  out.segments = s.vertex + 1 + chain->k + 1;
  return true;
}

// After scattering at a vertex with `bsdf`: 0 from a non-delta vertex (where
// a manifold connection was made), one more after a refraction through smooth
// glass, else −1 (the light that path reaches is not a manifold connection's).
int PathEstimator::manifoldChainAfter(int chain, const BSDF& bsdf, bool refracted) const {
  if (!bsdf.isDelta()) return 0;
  bool glass = refracted && dynamic_cast<const SmoothDielectric*>(&bsdf.material()) != nullptr;
  return glass && chain >= 0 && chain < settings_.manifold.maxChain ? chain + 1 : -1;
}

}  // namespace lb
