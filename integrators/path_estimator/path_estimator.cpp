#include "integrators/path_estimator/path_estimator.h"
#include "core/bsdfs/bsdf.h"
#include "core/sampling.h"
#include "integrators/direct_light.h"

namespace lb {

PathTracerSettings PathTracerSettings::read(Params& p, bool directionKeys) {
  PathTracerSettings s;
  if (directionKeys) {
    std::string sampling = p.getChoice("sampling", "bsdf", {"bsdf", "cosine", "uniform"},
                                       "how the next direction is sampled at a surface");
    s.sampling = sampling == "bsdf" ? DirectionSampling::Bsdf
                 : sampling == "cosine" ? DirectionSampling::Cosine
                                        : DirectionSampling::Uniform;
  }
  s.nee = p.getBool("nee", true, "next-event estimation: shadow rays to sampled light points at each vertex");
  // variance_aware's factors are per pixel, learned by the path integrator's
  // passes: the estimator's other users (guided, which reads no direction
  // keys, the irradiance cache, MLT) have no pixel to learn them for.
  std::vector<std::string> heuristics = {"power", "balance", "none", "one_sample"};
  std::string meaning =
      "weights of NEE against the sampled direction hitting a light (Veach 1997, 9.2); one_sample picks one of the "
      "two per vertex";
  if (directionKeys) {
    heuristics.push_back("variance_aware");
    meaning += "; variance_aware: the balance heuristic scaled by each technique's learned second moment over "
               "variance (Grittmann et al. 2019)";
  }
  std::string mis = p.getChoice("mis", "power", heuristics, meaning);
  s.mis = mis == "power"          ? MisHeuristic::Power
          : mis == "balance"      ? MisHeuristic::Balance
          : mis == "none"         ? MisHeuristic::None
          : mis == "one_sample"   ? MisHeuristic::OneSample
                                  : MisHeuristic::VarianceAware;
  if (s.mis == MisHeuristic::VarianceAware || (p.describing() && directionKeys)) {
    p.setCondition("mis: variance_aware");
    s.pilotPasses = p.getInt("pilot_passes", 1,
                             {"first passes, weighted by the balance heuristic, whose samples estimate each "
                              "technique's moments (kept in the image)",
                              Range::between(1, 64)});
    s.factorBlock = std::stoi(p.getChoice("factor_block", "8", {"1", "2", "4", "8", "16"},
                                          "pixels per side of the square blocks over which the moments are pooled"));
    p.setCondition("");
  }
  s.lightSelectionProbability =
      p.getFloat("light_selection_probability", 0.5f,
                 {"mis: one_sample: probability of taking the light sample at a vertex", Range::open(0, 1)});
  s.emissionSelection = p.getFloat(
      "emission_selection", 0.f,
      {"emit vs reflect: at an emitter the path ends, counting its emission, with this probability (0: off)",
       Range{0.0, 1.0, false, true}});
  s.shadowRays = p.getInt("shadow_rays", 1, {"light samples (shadow rays) per vertex", Range::between(1, 64)});
  if (directionKeys)
    s.firstBounceSamples = p.getInt("first_bounce_samples", 1,
                                    {"directions sampled at the first vertex, each traced on", Range::between(1, 64)});
  std::string lights = p.getChoice(
      "light_selection", "scene", {"scene", "uniform", "power", "spatial"},
      "which light NEE samples: the scene's rule, uniformly, by power, or by a per-voxel estimate of contribution");
  s.lightSelection = lights == "scene"     ? LightChoice::Scene
                     : lights == "uniform" ? LightChoice::Uniform
                     : lights == "power"   ? LightChoice::Power
                                           : LightChoice::Spatial;
  if (directionKeys)
    s.wavefront = p.getChoice("engine", "single_ray", {"single_ray", "wavefront"},
                              "one path at a time, or all of a batch's rays in Embree streams (wavefront.h)") ==
                  "wavefront";
  s.misCompensation = p.getBool("mis_compensation", false,
                                "NEE samples an environment map with its mean subtracted (zero below it), leaving "
                                "those directions to BSDF sampling under MIS (Karlik et al. 2019, as pbrt-v4)");
  s.length = PathLength::read(p);
  // Learned roulette and splitting learn per pixel from the passes of the
  // integrator (path or guided, which both render a camera sample per pixel
  // per pass and own the cache: roulette_splitting.h's RrsLearning).
  std::string rrs = p.getChoice(
      "rrs", "classic", {"classic", "adrrs", "ears"},
      "Russian roulette and splitting: classic (rr's, on the throughput), adrrs (a weight window around the pixel "
      "estimate, Vorba & Krivanek 2016) or ears (efficiency-aware, Rath et al. 2022), both from a cache learned "
      "between passes");
  s.rrs = rrs == "classic" ? RrsMethod::Classic : rrs == "adrrs" ? RrsMethod::Adrrs : RrsMethod::Ears;
  if (directionKeys) {
    s.regularization = RegularizationSettings::read(p);
    s.mnee = p.getBool("mnee", false,
                       "manifold next-event estimation (Hanika et al. 2015): light samples behind smooth glass or "
                       "water connect through it by Newton's method; biased where a chain has several solutions");
    if (s.mnee || p.describing()) {
      p.setCondition("mnee: true");
      s.manifold.maxChain = p.getInt("mnee_max_chain", 2,
                                     {"refracting surfaces a manifold connection may cross (1: a water surface, 2: "
                                      "into and out of a glass sphere)",
                                      Range::between(1, ManifoldConnection::MaxChain)});
      p.setCondition("");
    }
    std::string sms = p.getChoice(
        "sms", "off", {"off", "unbiased", "biased"},
        "specular manifold sampling (Zeltner et al. 2020): like mnee through one or two refracting or mirror surfaces, Newton's method "
        "started from random points of the glass or mirrors; unbiased weighs each solution by a Bernoulli estimate of 1/p, "
        "biased sums the distinct solutions of sms_trials starts");
    s.sms = sms == "off" ? SmsMode::Off : sms == "unbiased" ? SmsMode::Unbiased : SmsMode::Biased;
    if (s.sms != SmsMode::Off || p.describing()) {
      p.setCondition("sms: unbiased or biased");
      s.smsTrials = p.getInt("sms_trials", 64,
                             {"unbiased: the most starts counted for 1/p (fewer bias solutions found with p < 1/this); "
                              "biased: the starts whose distinct solutions are summed",
                              Range::between(1, 100000)});
      s.manifold.maxChain = ManifoldConnection::MaxChain;
      p.setCondition("");
    }
  }
  if (s.rrs != RrsMethod::Classic || p.describing()) {
    p.setCondition("rrs: adrrs or ears");
    s.rrsWarmup = p.getInt("rrs_warmup", 4,
                           {"first passes with classic roulette, whose continuations only fill the cache",
                            Range::between(1, 1 << 20)});
    s.rrsCells = p.getInt("rrs_cells", 8,
                          {"the cache's cells along the scene's longest side (each with 4 x 4 direction bins)",
                           Range::between(1, 32)});
    s.rrsMinSamples = p.getInt("rrs_min_samples", 64,
                               {"continuations a cache bin needs before it is used (else its cell's, else classic "
                                "roulette)",
                                Range::atLeast(1)});
    s.rrsSplitLight = p.getBool("rrs_split_light", true,
                                "the vertex's light samples are split and rouletted with its continuation, as the "
                                "authors' code does; false: the light samples are taken once, only the continuation "
                                "is split");
    p.setCondition("");
  }
  // Compensated densities are zero where the map is below its mean: only
  // BSDF sampling, weighted against the same densities, reaches there.
  if (s.misCompensation && (!s.nee || s.mis == MisHeuristic::None))
    p.fail("mis_compensation", "needs next-event estimation weighted by MIS against BSDF sampling (nee: true, "
                               "mis: power, balance or one_sample)");
  if (s.misCompensation && s.sampling != DirectionSampling::Bsdf)
    p.fail("mis_compensation", "needs sampling: bsdf (cosine and uniform sampling miss transmitted directions)");
  if (s.mis == MisHeuristic::VarianceAware) {
    if (s.wavefront) p.fail("engine", "mis: variance_aware runs on engine: single_ray");
    if (s.firstBounceSamples > 1)
      p.fail("first_bounce_samples", "mis: variance_aware counts one BSDF sample per vertex; use 1");
    if (s.emissionSelection > 0)
      p.fail("emission_selection", "mis: variance_aware learns from the emission counted in full; use 0");
  }
  if (s.rrs != RrsMethod::Classic) {
    if (s.wavefront) p.fail("engine", "rrs: adrrs and ears split paths; use engine: single_ray");
    if (s.firstBounceSamples > 1)
      p.fail("first_bounce_samples", "rrs: adrrs and ears choose how often to split; use 1");
    if (s.mis == MisHeuristic::VarianceAware)
      p.fail("mis", "rrs: adrrs and ears run with power, balance, none or one_sample");
    // A learned factor may stay ≥ 1 along a path (a white furnace): only max_depth ends it then.
    if (s.length.maxDepth < 0) p.fail("max_depth", "rrs: adrrs and ears need a finite max_depth");
  }
  if (s.regularization.enabled && s.sampling != DirectionSampling::Bsdf)
    p.fail("sampling", "regularize: the rough twins of glass transmit, which cosine and uniform sampling miss; use "
                       "sampling: bsdf");
  if (s.regularization.enabled && s.wavefront)
    p.fail("engine", "regularize: the single-ray engine prepares each pass's rough twins; use engine: single_ray");
  if (s.mnee && s.sms != SmsMode::Off) p.fail("sms", "mnee and sms both connect through the glass; choose one");
  if (s.sms != SmsMode::Off && !s.nee) p.fail("sms", "specular manifold sampling is a kind of next-event estimation; use nee: true");
  if (s.sms != SmsMode::Off && s.wavefront) p.fail("engine", "sms: the single-ray engine solves each manifold connection; use engine: single_ray");
  if (s.sms != SmsMode::Off && s.regularization.enabled)
    p.fail("regularize", "sms and regularize both replace the paths through glass after a diffuse vertex; choose one");
  if (s.mnee && !s.nee) p.fail("mnee", "manifold next-event estimation is a kind of next-event estimation; use nee: true");
  // variance_aware's pilots learn light against BSDF sampling; a manifold
  // connection is neither, and would count in its moments as a light sample.
  if ((s.mnee || s.sms != SmsMode::Off) && s.mis == MisHeuristic::VarianceAware)
    p.fail("mis", "mnee and sms run with power, balance, none or one_sample");
  if (s.mnee && s.wavefront) p.fail("engine", "mnee: the single-ray engine solves each manifold connection; use engine: single_ray");
  if (s.mnee && s.regularization.enabled)
    p.fail("regularize", "mnee and regularize both replace the paths through glass after a diffuse vertex; choose one");
  if (s.wavefront && s.firstBounceSamples > 1)
    p.fail("first_bounce_samples", "engine: wavefront does not branch paths; use engine: single_ray");
  if (s.mis == MisHeuristic::OneSample && s.shadowRays > 1)
    p.fail("shadow_rays", "mis: one_sample takes one light sample or none at a vertex; use shadow_rays: 1");
  p.checkUnused();
  return s;
}

OneSampleWeights oneSampleMisWeights(float q, float lightPdf, float bsdfPdf) {
  float light = q * lightPdf, bsdf = (1 - q) * bsdfPdf;
  if (!(light + bsdf > 0)) return {0.f, 0.f};
  return {light / (light + bsdf), bsdf / (light + bsdf)};
}

void PathEstimator::preprocess(const Scene& scene, uint64_t seed) {
  if (settings_.lightSelection == LightChoice::Uniform) ownLights_ = LightSampler(scene.lights(), LightSelection::Uniform);
  if (settings_.lightSelection == LightChoice::Power) ownLights_ = LightSampler(scene.lights(), LightSelection::Power);
  if (settings_.lightSelection == LightChoice::Spatial)
    spatial_ = std::make_shared<SpatialLightSampler>(scene, hashValues(seed, 0x5ba71a1));
  if (settings_.sms != SmsMode::Off) prepareSmsCasters(scene);
}

const Light* PathEstimator::chooseLight(const Scene& scene, const Vec3& p, float u, float* pmf) const {
  switch (settings_.lightSelection) {
    case LightChoice::Spatial: return spatial_->sample(p, u, pmf);
    case LightChoice::Uniform:
    case LightChoice::Power: return ownLights_.sample(u, pmf);
    default: return scene.lightSampler().sample(u, pmf);
  }
}

float PathEstimator::lightPmf(const Scene& scene, const Vec3& p, const Light* light) const {
  switch (settings_.lightSelection) {
    case LightChoice::Spatial: return spatial_->pmf(p, light);
    case LightChoice::Uniform:
    case LightChoice::Power: return ownLights_.pmf(light);
    default: return scene.lightSampler().pmf(light);
  }
}

// Multi-sample MIS with sample counts (Veach 1997 Eq. 9.13): the heuristic of
// n_i p_i against n_j p_j.
float PathEstimator::misWeight(float nThis, float pdfThis, float nOther, float pdfOther) const {
  switch (settings_.mis) {
    case MisHeuristic::Power: return powerHeuristic(nThis * pdfThis, nOther * pdfOther);
    case MisHeuristic::Balance:
    case MisHeuristic::VarianceAware: return balanceHeuristic(nThis * pdfThis, nOther * pdfOther);
    default: return 1.f;
  }
}

Color PathEstimator::incidentRadiance(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays, int maxDepth,
                                   bool firstEmission, float* firstHitDistance,
                                   const VarianceAwareView* varianceAware, const RrsView* rrs,
                                   const Regularization* regularization) const {
  if (firstHitDistance) *firstHitDistance = Infinity;
  if (maxDepth < 1) return Color(0.f);  // max_depth 0 renders black
  PathState state;
  state.ray = ray;
  state.prevPoint = ray.o;
  PathContext ctx{scene, sampler, maxDepth, firstEmission, sampler.dimension(), nullptr, varianceAware, rrs,
                  regularization};
  return trace(state, ctx, rays, firstHitDistance, nullptr);
}

// The single-ray engine: one path, depth first, each shadow ray traced as
// soon as it is made.
Color PathEstimator::trace(PathState& s, const PathContext& c, uint64_t& rays, float* firstHitDistance,
                           PathObserver* observer) const {
  const int M = settings_.firstBounceSamples;
  Color L(0.f);
  ShadowRequest shadows[MaxShadowRequests];
  Continuation pending[MaxRecordedVertices];  // rrs: this line's continuations, recorded when it ends
  int pendingCount = 0;
  for (;; ++s.vertex) {
    SurfaceInteraction si;
    ++rays;
    bool hit = c.scene.intersect(s.ray, si);
    if (s.vertex == 0 && hit && firstHitDistance) *firstHitDistance = si.t;
    std::optional<BSDF> bsdf;
    const Color before = L;
    int requests = shadeVertex(s, hit, si, c, L, shadows, bsdf);
    const Color afterEmission = L;
    const uint64_t raysBeforeShadows = rays;
    // rrs: the light samples are split (or rouletted) with the continuation,
    // so the vertex decides before they are traced (path_splitting.cpp).
    SplitDecision decision;
    const bool splitLight = c.rrs && settings_.rrsSplitLight;
    if (c.rrs && bsdf) {
      decision = decideSplit(s, si, *bsdf, c);
      if (decision.learned && splitLight) {
        if (decision.n == 0) requests = 0;  // rouletted: nor are its light samples taken
        for (int i = 0; i < requests; ++i) shadows[i].contribution /= decision.q;
      }
    }
    for (int i = 0; i < requests; ++i) {
      if (!shadows[i].tested) {
        ++rays;
        if (c.scene.occluded(shadows[i].ray)) continue;
      }
      L += shadows[i].contribution;
      if (c.varianceAware) c.varianceAware->record(shadows[i].segments, MisTechnique::Light, shadows[i].unweighted);
    }
    if (observer) observer->shaded(si, bsdf ? &*bsdf : nullptr, afterEmission - before, L - before);
    if (!bsdf) break;
    // M branches at the first vertex, each carrying β/M and its own slots.
    if (s.vertex == 0 && M > 1) {
      for (int b = 0; b < M; ++b) {
        PathState next = s;
        next.beta /= float(M);
        next.branch = b;
        if (scatter(next, si, *bsdf, c.sampler, vertexBase(next, c), c.guide)) {
          if (observer) observer->scattered(si, next);
          ++next.vertex;
          L += trace(next, c, rays, nullptr, observer);
        }
      }
      break;
    }
    if (c.rrs) {
      if (!split(s, si, *bsdf, c, decision, splitLight ? L - afterEmission : Color(0.f),
                 splitLight ? rays - raysBeforeShadows : 0, rays, L, observer, pending, pendingCount))
        break;
    } else if (!scatter(s, si, *bsdf, c.sampler, vertexBase(s, c), c.guide)) {
      break;
    }
    if (observer) observer->scattered(si, s);
  }
  // What each continuation of this line brought back, per unit throughput.
  for (int i = 0; i < pendingCount; ++i) {
    const Continuation& k = pending[i];
    c.rrs->record(k.slot, k.direct + perUnitThroughput(L - k.before, k.beta), double(rays - k.rays));
  }
  return L;
}

int PathEstimator::shadeVertex(PathState& s, bool hit, const SurfaceInteraction& si, const PathContext& c, Color& L,
                            ShadowRequest* shadows, std::optional<BSDF>& bsdfOut) const {
  bsdfOut.reset();
  const float q = settings_.lightSelectionProbability;
  const int segments = s.vertex + 1;
  const uint32_t base = vertexBase(s, c);
  Sampler& sampler = c.sampler;
  bool countEmission = segments > 1 || c.firstEmission;

  // The density with which the previous vertex's NEE would have sampled
  // this point of `light` (the compensated one if NEE used it).
  auto lightPdf = [&](const Light& light, const Vec3& ref, const Vec3& wi, const Vec3& p, const Vec3& n) {
    return settings_.misCompensation ? light.pdfLiCompensated(ref, wi, p, n) : light.pdfLi(ref, wi, p, n);
  };
  auto factor = [&](int length, MisTechnique t) { return techniqueFactor(c, length, t); };
  // A BSDF-sampled segment reaching emission L_e (times β): its unweighted
  // estimate, where it competes with light sampling, is a variance-aware pilot's sample.
  auto recordEmission = [&](const Color& betaLe) {
    if (c.varianceAware && !s.prevDelta && settings_.nee)
      c.varianceAware->record(segments, MisTechnique::Bsdf, luminance(betaLe));
  };
  // Emission reached by this segment, MIS-weighted against the previous
  // vertex's light samples.
  auto emissionWeight = [&](const Light* light, float pdfLi) {
    if (s.prevDelta || !settings_.nee) return 1.f;
    float pdfLight = lightPmf(c.scene, s.prevPoint, light) * pdfLi;
    switch (settings_.mis) {
      case MisHeuristic::None: return 0.f;
      // w_f / (1 − q): the division by the strategy's selection probability.
      case MisHeuristic::OneSample:
        return s.prevLightChosen ? 0.f : oneSampleMisWeights(q, pdfLight, s.prevPdf).bsdf / (1 - q);
      default:
        return misWeight(s.prevBsdfCount * factor(segments, MisTechnique::Bsdf), s.prevPdf,
                         float(settings_.shadowRays) * factor(segments, MisTechnique::Light), pdfLight);
    }
  };
  if (!hit) {
    if (!countEmission) return 0;
    for (const Light* env : c.scene.infiniteLights()) {
      Color Le = env->Le(s.ray.d);
      if (isBlack(Le)) continue;
      L += s.beta * Le * emissionWeight(env, lightPdf(*env, s.prevPoint, s.ray.d, {}, {}));
      recordEmission(s.beta * Le);
    }
    return 0;
  }
  bool canContinue = segments < c.maxDepth && si.material;
  // mnee: a light reached through 1 … max_chain refractions after a
  // non-delta vertex is that vertex's manifold connection's to count.
  bool manifoldCovers = (settings_.mnee || settings_.sms != SmsMode::Off) && s.manifoldChain >= 1;
  if (si.emitter && countEmission && !manifoldCovers) {
    Color Le = si.emitter->L(si.ng, si.wo);
    recordEmission(s.beta * Le);
    Color emitted = isBlack(Le) ? Color(0.f)
                                : s.beta * Le *
                                      emissionWeight(si.emitter, lightPdf(*si.emitter, s.prevPoint, s.ray.d, si.p, si.ng));
    // Emit vs reflect: one of the two terms of the rendering equation, each
    // divided by the probability of choosing it.
    if (!isBlack(emitted) && canContinue && settings_.emissionSelection > 0) {
      sampler.setDimension(base + 0);
      float p = settings_.emissionSelection;
      if (sampler.get1D() < p) {
        L += emitted / p;
        return 0;
      }
      s.beta /= 1 - p;
    } else {
      L += emitted;
    }
  }
  if (!canContinue) return 0;
  // regularize: a delta vertex after a non-delta one scatters by its
  // material's rough twin (regularization.h), light samples included.
  const Material* twin = c.regularization && s.pastNonDelta ? c.regularization->twin(si.material) : nullptr;
  const BSDF& bsdf = twin ? bsdfOut.emplace(si, twin) : bsdfOut.emplace(si);
  bool guided = c.guide && c.guide->prepare(si, bsdf);
  return lightSamples(s, si, bsdf, c, guided, shadows);
}

int PathEstimator::lightSamples(PathState& s, const SurfaceInteraction& si, const BSDF& bsdf, const PathContext& c,
                                bool guided, ShadowRequest* shadows) const {
  const float q = settings_.lightSelectionProbability;
  const int segments = s.vertex + 1;
  const uint32_t base = vertexBase(s, c);
  Sampler& sampler = c.sampler;
  auto factor = [&](int length, MisTechnique t) { return techniqueFactor(c, length, t); };
  bool delta = bsdf.isDelta();
  bool hemisphere = settings_.sampling != DirectionSampling::Bsdf && !delta;
  float bsdfCount = s.vertex == 0 ? float(settings_.firstBounceSamples) : 1.f;
  // The density with which scatter() would have drawn a light sample's direction.
  auto scatterPdf = [&](const DirectLightSample& d) {
    if (guided) return c.guide->mixturePdf(d.bsdfPdf, d.wi);
    return hemisphere ? hemispherePdf(settings_.sampling, bsdf, si.wo, d.wi) : d.bsdfPdf;
  };
  // Light sample (shadow ray) i at this vertex: slots 2 + 4i … 5 + 4i.
  auto lightSample = [&](int i) {
    sampler.setDimension(base + 2 + 4 * uint32_t(i));
    float pmf = 0;
    const Light* light = chooseLight(c.scene, si.p, sampler.get1D(), &pmf);
    float uPick = sampler.get1D();
    Vec2 u = sampler.get2D();
    return directLightQuery(si, bsdf, light, pmf, uPick, u, settings_.misCompensation);
  };

  // Next-event estimation.
  int n = 0;
  bool lightChosen = false;
  if (settings_.nee && !delta && !c.scene.lightSampler().empty()) {
    if (settings_.mis == MisHeuristic::OneSample) {
      sampler.setDimension(base + 1);
      lightChosen = sampler.get1D() < q;
      if (lightChosen)
        if (auto d = lightSample(0)) {
          float w = d->sample.deltaLight ? 1.f : oneSampleMisWeights(q, d->sample.lightPdf, scatterPdf(d->sample)).light;
          shadows[n++] = {d->shadowRay, s.beta * d->sample.contribution * (w / q)};
        }
    } else {
      const int N = settings_.shadowRays;
      const int length = segments + 1;  // the light sample's path: this vertex's, plus the segment to the light
      for (int i = 0; i < N; ++i)
        if (auto d = lightSample(i)) {
          bool weighted = !d->sample.deltaLight;
          float w = weighted ? misWeight(float(N) * factor(length, MisTechnique::Light), d->sample.lightPdf,
                                         bsdfCount * factor(length, MisTechnique::Bsdf), scatterPdf(d->sample))
                             : 1.f;
          Color unweighted = s.beta * d->sample.contribution;
          float pilotValue = c.varianceAware && weighted ? luminance(unweighted) : 0.f;
          shadows[n++] = {d->shadowRay, unweighted * (w / float(N)), pilotValue, length};
        }
    }
  }
  // Manifold next-event estimation: one more light sample, connected
  // through the glass its straight segment crosses (manifold_nee.cpp).
  if ((settings_.mnee || settings_.sms != SmsMode::Off) && !delta && !c.scene.lightSampler().empty())
    if (manifoldLightSample(s, si, bsdf, c, base + settings_.manifoldSlot(), shadows[n])) ++n;
  s.prevLightChosen = lightChosen;
  s.prevBsdfCount = bsdfCount;
  return n;
}

bool PathEstimator::scatter(PathState& next, const SurfaceInteraction& si, const BSDF& bsdf, Sampler& sampler,
                         uint32_t slots, const DirectionGuide* guide, bool roulette) const {
  bool hemisphere = settings_.sampling != DirectionSampling::Bsdf && !bsdf.isDelta();
  sampler.setDimension(slots + settings_.scatterSlot());
  float uLobe = sampler.get1D();
  Vec2 uDir = sampler.get2D();
  Vec3 wi;
  bool refracted = false, reflected = false;  // by a delta transmission or reflection lobe
  // A direction drawn by some other density than the BSDF's own sampling:
  // f·|cos θ| / pdf, with f evaluated for it (or known).
  auto takeDirection = [&](const Vec3& d, float pdf, const Color* knownF = nullptr) {
    Color f = knownF ? *knownF : bsdf.eval(si.wo, d, TransportMode::Radiance).f;
    if (!(pdf > 0) || isBlack(f)) return false;
    next.beta *= f * absDot(d, bsdf.shadingNormal()) / pdf;
    if (glm::dot(d, si.ng) * glm::dot(si.wo, si.ng) < 0)
      next.etaScale *= sqr(bsdf.material().relativeEta(bsdf.frame().toLocal(si.wo)));
    wi = d;
    next.prevPdf = pdf;
    next.prevDelta = false;
    return true;
  };
  if (guide && guide->active()) {
    // One-sample mixture (direction_guide.h): either component may draw the
    // direction; its weight uses the mixture's density.
    // (A non-delta BSDF's sample carries f(wo, wi) and pdf(wo, wi) of its
    // direction, material.h; the guide's sample, its own density.)
    float c = guide->bsdfFraction();
    if (uLobe < c) {
      auto bs = bsdf.sample(si.wo, std::min(uLobe / c, OneMinusEpsilon), uDir, TransportMode::Radiance);
      if (!bs) return false;
      if (!takeDirection(bs->wi, c * bs->pdf + (1 - c) * guide->pdf(bs->wi), &bs->f)) return false;
    } else {
      float guidePdf = 0;
      Vec3 d = guide->sample(uDir, &guidePdf);
      if (!takeDirection(d, c * bsdf.pdf(si.wo, d) + (1 - c) * guidePdf)) return false;
    }
  } else if (hemisphere) {
    DirectionChoice d = sampleHemisphere(settings_.sampling, bsdf, si.wo, uLobe, uDir);
    if (!takeDirection(d.wi, d.pdf)) return false;
  } else {
    auto bs = bsdf.sample(si.wo, uLobe, uDir, TransportMode::Radiance);
    if (!bs) return false;
    next.beta *= bs->weight;
    if (bs->lobe & BSDFTransmission) next.etaScale *= sqr(bs->eta);
    refracted = bs->isDelta() && (bs->lobe & BSDFTransmission);
    reflected = bs->isDelta() && (bs->lobe & BSDFReflection);
    wi = bs->wi;
    next.prevPdf = bs->pdf;
    next.prevDelta = bs->isDelta();
  }
  if (isBlack(next.beta)) return false;
  if (!bsdf.isDelta()) next.pastNonDelta = true;
  if (settings_.mnee || settings_.sms != SmsMode::Off)
    next.manifoldChain = manifoldChainAfter(next.manifoldChain, bsdf, refracted, reflected);
  next.prevPoint = si.p;
  next.ray = si.spawnRay(wi);
  return !roulette || survivesRoulette(next, sampler, slots);
}

bool PathEstimator::survivesRoulette(PathState& next, Sampler& sampler, uint32_t slots, float* survival) const {
  const int segments = next.vertex + 1;
  sampler.setDimension(slots + settings_.scatterSlot() + 3);
  if (survival) *survival = settings_.length.survivalProbability(segments, next.beta, next.etaScale);
  return settings_.length.survivesRoulette(segments, next.beta, next.etaScale, sampler);
}

}  // namespace lb
