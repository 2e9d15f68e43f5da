#include "integrators/direct_optimal/direct_optimal.h"
#include "core/bsdfs/bsdf.h"
#include <stdexcept>

namespace lb {

DirectOptimalSettings DirectOptimalSettings::read(Params& p) {
  DirectOptimalSettings s;
  s.optimal = p.getChoice("mis", "optimal", {"optimal", "balance"},
                          "optimal: per-pixel α from the pixel's earlier samples (Kondapaneni et al. 2019); "
                          "balance: α = 0, the balance heuristic") == "optimal";
  s.pilotPasses = p.getInt("pilot_passes", 4,
                           {"a pixel's first samples, weighted by the balance heuristic, before its α is used "
                            "(they still count in its sums)",
                            Range::atLeast(0)});
  p.checkUnused();  // an unknown key is an error naming the valid ones
  return s;
}

void DirectOptimal::preprocess(const Scene& scene, const Sampler& prototype) {
  // α is a function of the pixel's earlier numbers; a sample is unbiased
  // under it only if its own numbers are independent of those, which a
  // low-discrepancy sequence's are not (as for path's learned states).
  if (settings_.optimal && !dynamic_cast<const IndependentSampler*>(&prototype))
    throw std::invalid_argument(
        "direct_optimal, mis: optimal: each sample uses the coefficients learned from the pixel's earlier samples, "
        "so their random numbers must be independent: use sampler type independent");
  width_ = scene.camera.width();
  sums_.assign(size_t(width_) * scene.camera.height(), OptimalMisSums{});
}

namespace {

// The light technique's density at a point an emitter's light sample could
// have produced: sampleLi refuses points whose emission is black (an area
// light's back), so there the density is 0.
float lightTechniquePdf(const LightSampler& lights, const Light* light, const Color& Le, float pdfLi) {
  if (!light->isInfinite() && isBlack(Le)) return 0;
  return lights.pmf(light) * pdfLi;
}

// A direction at infinity belongs to every infinite light: the radiance
// arriving along `d` and the light technique's density of it are the sums
// over them (for a light sample from any of them and a BSDF sample that escapes).
struct AtInfinity {
  Color Le{0.f};
  float pLight = 0;
};
AtInfinity atInfinity(const Scene& scene, const LightSampler& lights, const Vec3& ref, const Vec3& d) {
  AtInfinity a;
  for (const Light* env : scene.infiniteLights()) {
    Color Le = env->Le(d);
    a.Le += Le;
    a.pLight += lightTechniquePdf(lights, env, Le, env->pdfLi(ref, d, {}, {}));
  }
  return a;
}

}  // namespace

Color DirectOptimal::pixelLi(int x, int y, const Ray& ray, const Scene& scene, Sampler& sampler,
                             uint64_t& rays) const {
  // The camera ray: emitters seen directly, outside the combination.
  SurfaceInteraction si;
  ++rays;
  if (!scene.intersect(ray, si)) {
    Color L(0.f);
    for (const Light* env : scene.infiniteLights()) L += env->Le(ray.d);
    return L;
  }
  Color L = si.emitter ? si.emitter->L(si.ng, si.wo) : Color(0.f);
  if (!si.material) return L;
  BSDF bsdf(si);
  const LightSampler& lights = scene.lightSampler();
  OptimalMisSums& sums = sums_[size_t(y) * width_ + x];
  OmisAlpha alpha{glm::dvec3(0), glm::dvec3(0)};
  // A material whose pdf is an estimate (layered) keeps α = 0 and records
  // nothing: the balance heuristic's weights only need to sum to 1, the
  // control variates need the true density.
  bool exact = bsdf.material().exactDensity();
  if (settings_.optimal && exact && sums.rounds() >= uint64_t(settings_.pilotPasses)) alpha = sums.solve();
  if (exact) sums.countRound();

  OmisSample samples[OmisTechniques];
  int count = 0;
  std::array<bool, OmisTechniques> produced{false, false};

  // Technique 0, the light sample (the same sampler dimensions as `direct`).
  float pmf = 0;
  const Light* light = lights.empty() ? nullptr : lights.sample(sampler.get1D(), &pmf);
  float uPick = sampler.get1D();
  Vec2 u = sampler.get2D();
  if (light && pmf > 0 && !bsdf.isDelta()) {
    auto ls = light->sampleLi(si.p, uPick, u);
    if (ls && ls->pdf > 0) {
      BSDFEval e = bsdf.eval(si.wo, ls->wi, TransportMode::Radiance);
      Color f = e.f * absDot(ls->wi, bsdf.shadingNormal()) * ls->L;
      bool needsRay = !isBlack(f) || (!light->isDelta() && e.pdf > 0);
      bool visible = false;
      if (needsRay) {
        ++rays;
        visible = !scene.occluded(si.spawnRayTo(ls->p, ls->pError, ls->n));
      }
      if (light->isDelta()) {
        if (visible) L += f / pmf;  // a point or directional light: its own technique alone
      } else {
        produced[0] = true;
        float pLight = pmf * ls->pdf;
        if (light->isInfinite()) {  // every infinite light's, not only this one's
          AtInfinity a = atInfinity(scene, lights, si.p, ls->wi);
          f = e.f * absDot(ls->wi, bsdf.shadingNormal()) * a.Le;
          pLight = a.pLight;
        }
        // Occluded: the BSDF technique would have stopped at the occluder.
        samples[count++] = OmisSample{visible ? f : Color(0.f), {pLight, visible ? e.pdf : 0.f}};
      }
    }
  }

  // Technique 1, the BSDF sample.
  Vec2 uDir = sampler.get2D();
  float uLobe = sampler.get1D();
  auto bs = bsdf.sample(si.wo, uLobe, uDir, TransportMode::Radiance);
  if (bs && bs->pdf > 0) {
    Ray next = si.spawnRay(bs->wi);
    SurfaceInteraction hit;
    ++rays;
    Color Le(0.f);
    float pLight = 0;
    if (!scene.intersect(next, hit)) {
      AtInfinity a = atInfinity(scene, lights, si.p, next.d);
      Le = a.Le, pLight = a.pLight;
    } else if (hit.emitter) {
      Le = hit.emitter->L(hit.ng, hit.wo);
      pLight = lightTechniquePdf(lights, hit.emitter, Le, hit.emitter->pdfLi(si.p, next.d, hit.p, hit.ng));
    }
    if (bs->isDelta()) {
      L += bs->weight * Le;  // a delta lobe: no light sample reaches it
    } else {
      produced[1] = true;
      samples[count++] = OmisSample{bs->weight * bs->pdf * Le, {pLight, bs->pdf}};
    }
  }

  glm::dvec3 F = optimalMisEstimate(alpha, samples, count, produced);
  if (exact)
    for (int j = 0; j < count; ++j) sums.record(samples[j]);
  return L + Color(F);
}

}  // namespace lb
