// Connection strategies and their MIS weights (pbrt-v3 §16.3.3–16.3.4).
#include "integrators/bidirectional/connect.h"
#include "integrators/bidirectional/cost_split.h"

namespace lb::bidir {

namespace {

bool visible(const Scene& scene, const Vertex& a, const Vertex& b, uint64_t& rays) {
  ++rays;
  if (b.isInfiniteLight()) return !scene.occluded(a.si.spawnRay(glm::normalize(b.p - a.p)));
  Vec3 from = offsetRayOrigin(a.p, a.pError, a.ng, b.p - a.p);
  Vec3 to = offsetRayOrigin(b.p, b.pError, b.ng, from - b.p);
  return !scene.occluded({from, to - from, 1 - ShadowEpsilon});
}

}  // namespace

float misWeight(const Scene& scene, MisWeighting h, Subpath light,
                Subpath camera, const Vertex& sampled, int s, int t) {
  return techniqueWeights(scene, h, Techniques{}, light, camera, sampled, s, t).connection;
}

Connection connect(const Scene& scene, Sampler& sampler, MisWeighting mis, Subpath light,
                   Subpath camera, int s, int t, uint64_t& rays) {
  return connect(scene, sampler, mis, Techniques{}, light, camera, s, t, rays);
}

// Each strategy evaluates the BSDF once at each of its connection vertices:
// the value f, and with it both directional densities the weight needs
// (material.h: pdf towards the other subpath, pdfRev back along its own).
Connection connect(const Scene& scene, Sampler& sampler, MisWeighting mis, const Techniques& techniques,
                   Subpath light, Subpath camera, int s, int t,
                   uint64_t& rays) {
  PhaseScope phase(Phase::Connections);
  Connection c;
  // A camera path that escaped cannot be connected to anything.
  if (t > 1 && s != 0 && camera[size_t(t - 1)].type == VertexType::Light) return c;
  Vertex& sampled = c.sampled;
  ConnectionDensities rev;
  if (s == 0) {
    const Vertex& pt = camera[size_t(t - 1)];
    if (pt.isLight()) c.L = pt.beta * emitted(scene, pt, camera[size_t(t - 2)]);
    if (!isBlack(c.L)) {
      PhaseScope weights(Phase::Weights);
      rev = connectionDensities(scene, light, camera, sampled, s, t);
    }
  } else if (t == 1) {
    const Vertex& qs = light[size_t(s - 1)];
    // A regularized vertex next to the camera is not regularized on this path
    // (nothing non-delta lies between it and the camera): it stays a delta.
    if (qs.connectible() && qs.type == VertexType::Surface && !qs.regularized) {
      if (auto cam = scene.camera.connect(qs.p)) {
        sampled = cameraVertex(scene.camera, Color(cam->We / cam->pdf));
        BSDFEval e = BSDF(qs.si).eval(qs.si.wo, glm::normalize(sampled.p - qs.p), TransportMode::Importance);
        c.L = qs.beta * e.f * sampled.beta * absDot(cam->wi, qs.shadingNormal());
        c.raster = cam->raster;
        if (!isBlack(c.L) && !visible(scene, qs, sampled, rays)) c.L = Color(0.f);
        rev.qs = vertexPdf(scene, sampled, nullptr, qs);
        if (s >= 2) rev.qsMinus = convertDensity(qs, e.pdfRev, light[size_t(s - 2)]);
      }
    }
  } else if (s == 1) {
    const Vertex& pt = camera[size_t(t - 1)];
    if (pt.connectible() && pt.type == VertexType::Surface) {
      float pmf;
      const Light* l = scene.lightSampler().sample(sampler.get1D(), &pmf);
      float uPick = sampler.get1D();
      Vec2 u = sampler.get2D();
      if (l) {
        auto ls = l->sampleLi(pt.p, uPick, u);
        if (ls && ls->pdf > 0 && !isBlack(ls->L)) {
          sampled = lightVertex(l, ls->p, ls->n, ls->pError, ls->L / (ls->pdf * pmf), 0);
          sampled.pdfFwd = pdfLightOrigin(scene, sampled, pt);
          BSDFEval e = BSDF(pt.si).eval(pt.si.wo, ls->wi, TransportMode::Radiance);
          c.L = pt.beta * e.f * sampled.beta * absDot(ls->wi, pt.shadingNormal());
          if (!isBlack(c.L) && !visible(scene, pt, sampled, rays)) c.L = Color(0.f);
          const Vertex& ptMinus = camera[size_t(t - 2)];
          rev.pt = pdfLight(scene, sampled, pt);
          rev.ptMinus = convertDensity(pt, e.pdfRev, ptMinus);
          rev.qs = convertDensity(pt, e.pdf, sampled);
        }
      }
    }
  } else {
    const Vertex &qs = light[size_t(s - 1)], &pt = camera[size_t(t - 1)];
    Vec3 d = qs.p - pt.p;  // pt → qs
    float d2 = glm::dot(d, d);
    if (qs.connectible() && pt.connectible() && qs.type == VertexType::Surface && pt.type == VertexType::Surface &&
        d2 > 0) {
      // One distance for the BSDFs' direction, the geometry term and the two
      // densities across the connecting edge (convertDensity's |cos|/d², written
      // out: issue 33, a square root and two divisions each).
      Vec3 w = d / std::sqrt(d2);
      BSDFEval ep = BSDF(pt.si).eval(pt.si.wo, w, TransportMode::Radiance);
      BSDFEval eq = BSDF(qs.si).eval(qs.si.wo, -w, TransportMode::Importance);
      c.L = qs.beta * eq.f * ep.f * pt.beta;
      if (!isBlack(c.L)) {
        float g = 1 / d2 * absDot(qs.shadingNormal(), w) * absDot(pt.shadingNormal(), w);
        c.L *= g == 0 || !visible(scene, qs, pt, rays) ? 0.f : g;
      }
      rev.pt = eq.pdf * absDot(pt.ng, w) / d2;
      rev.ptMinus = convertDensity(pt, ep.pdfRev, camera[size_t(t - 2)]);
      rev.qs = ep.pdf * absDot(qs.ng, w) / d2;
      rev.qsMinus = convertDensity(qs, eq.pdfRev, light[size_t(s - 2)]);
    }
  }
  c.weight = isBlack(c.L) ? 0.f : techniqueWeights(scene, mis, techniques, light, camera, sampled, s, t, rev).connection;
  return c;
}

}  // namespace lb::bidir
