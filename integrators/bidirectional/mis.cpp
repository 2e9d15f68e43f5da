// O(1) MIS weights from partial sums (mis.h, Eqs. 1–6).
#include "integrators/bidirectional/mis.h"
#include "integrators/bidirectional/cost_split.h"

namespace lb::bidir {

namespace {

// In double: a merge's term (ρ · p · η)² can pass a float's range on paths
// that merging samples far better than anything else (its weight must then
// be ~1, not Inf/Inf).
double heuristic(MisWeighting h, double x) {
  switch (h) {
    case MisWeighting::Power: return x * x;
    case MisWeighting::Balance: return x;
    default: return x > 0 ? 1.0 : 0.0;  // uniform: count every strategy that can sample the path
  }
}

bool mergeable(const Vertex& v, bool delta) { return v.type == VertexType::Surface && !delta && v.connectible(); }

// The terms of one vertex, Eq. 2, given its own and its predecessor's delta
// flags (a connection clears the flag of its own vertices).
struct Terms {
  MisWeighting h;
  const Techniques& allowed;
  double merge(const Vertex& v, bool delta) const {
    return allowed.mergeEta > 0 && mergeable(v, delta) ? heuristic(h, double(v.pdfFwd) * allowed.mergeEta) : 0.0;
  }
  // h(n) of a connection with both s, t >= 2 (Techniques::connectionCount).
  double count() const { return heuristic(h, allowed.connectionCount); }
  // Camera vertex z_k, k >= 1: the connection of z_{k-1} and z_k (light
  // tracing for k = 1), a merge at z_k.
  double camera(const Vertex& v, int k, bool delta, bool deltaBefore) const {
    return (allowed.connections && !delta && !deltaBefore ? (k == 1 ? 1.0 : count()) : 0.0) + merge(v, delta);
  }
  // Light vertex y_k: k = 0 the camera subpath hitting y_0 (s = 0); k >= 1 the
  // connection of y_{k-1} and y_k (k = 1 by next-event estimation) and a merge at y_k.
  double light(const Vertex& v, int k, bool delta, bool deltaBefore, double nee) const {
    if (k == 0) return !delta && !deltaBefore ? 1.0 : 0.0;
    double c = allowed.connections && !delta && !deltaBefore ? (k == 1 ? heuristic(h, nee) : count()) : 0.0;
    return c + merge(v, delta);
  }
};

double ratio(double rev, double fwd) { return fwd > 0 ? rev / fwd : 0.0; }

}  // namespace

float neeOverEmit(const Scene& scene, const Vertex& y0, const Vertex& y1) {
  float pEmit = pdfLightOrigin(scene, y0, y1);
  return pEmit > 0 ? pdfLightNee(scene, y0, y1) / pEmit : 0.f;
}

void computePartialSums(const Scene& scene, MisWeighting h, const Techniques& allowed, std::vector<Vertex>& path,
                        int n, SubpathSide side) {
  if (n <= 0) return;
  PhaseScope phase(Phase::Weights);
  Terms terms{h, allowed};
  double sum = 0;
  bool zero = false;
  if (side == SubpathSide::Camera) {
    path[0].misSum = 0, path[0].misBaseZero = false;  // S_0 = 0: the camera's own vertex is never a connection's far end
    for (int k = 1; k < n; ++k) {
      Vertex& v = path[size_t(k)];
      zero |= !(v.pdfFwd > 0);
      sum = heuristic(h, ratio(v.pdfRev, v.pdfFwd)) * (terms.camera(v, k, v.delta, path[size_t(k - 1)].delta) + sum);
      v.misSum = sum, v.misBaseZero = zero;
    }
    return;
  }
  double nee = n >= 2 ? neeOverEmit(scene, path[0], path[1]) : 0.0;
  path[0].neeOverEmit = float(nee);
  for (int k = 0; k < n; ++k) {
    Vertex& v = path[size_t(k)];
    zero |= !(v.pdfFwd > 0);
    bool deltaBefore = k > 0 ? path[size_t(k - 1)].delta : path[0].isDeltaLight();
    sum = heuristic(h, ratio(v.pdfRev, v.pdfFwd)) * (terms.light(v, k, v.delta, deltaBefore, nee) + sum);
    v.misSum = sum, v.misBaseZero = zero;
  }
}

namespace {
// The connection's vertices; the freshly sampled endpoint replaces the
// subpath's own for s = 1 / t = 1 (a merge keeps its emission-sampled y0).
struct Ends {
  const Vertex *qs, *pt, *qsMinus, *ptMinus;
  Ends(Subpath light, Subpath camera, const Vertex& sampled, int s, int t,
       const Vertex* merged)
      : qs(s == 0 ? nullptr : s == 1 && !merged ? &sampled : &light[size_t(s - 1)]),
        pt(t == 1 ? &sampled : &camera[size_t(t - 1)]),
        qsMinus(s > 1 ? &light[size_t(s - 2)] : nullptr),
        ptMinus(t > 1 ? &camera[size_t(t - 2)] : nullptr) {}
};
}  // namespace

ConnectionDensities connectionDensities(const Scene& scene, Subpath light,
                                        Subpath camera, const Vertex& sampled, int s, int t,
                                        const Vertex* merged) {
  Ends e(light, camera, sampled, s, t, merged);
  ConnectionDensities d;
  if (e.ptMinus)
    d.pt = merged ? merged->pdfFwd
                  : s > 0 ? vertexPdf(scene, *e.qs, e.qsMinus, *e.pt) : pdfLightOrigin(scene, *e.pt, *e.ptMinus);
  if (t >= 3) d.ptMinus = s > 0 ? vertexPdf(scene, *e.pt, e.qs, *e.ptMinus) : pdfLight(scene, *e.pt, *e.ptMinus);
  if (e.qs) d.qs = vertexPdf(scene, *e.pt, e.ptMinus, *e.qs);
  if (e.qsMinus) d.qsMinus = merged ? e.qsMinus->pdfRev : vertexPdf(scene, *e.qs, e.pt, *e.qsMinus);
  return d;
}

TechniqueWeights techniqueWeights(const Scene& scene, MisWeighting h, const Techniques& allowed,
                                  Subpath light, Subpath camera,
                                  const Vertex& sampled, int s, int t, const Vertex* merged) {
  if (s + t == 2) return {1.f, 0.f};
  return techniqueWeights(scene, h, allowed, light, camera, sampled, s, t,
                          connectionDensities(scene, light, camera, sampled, s, t, merged), merged);
}

TechniqueWeights techniqueWeights(const Scene& scene, MisWeighting h, const Techniques& allowed,
                                  Subpath light, Subpath camera,
                                  const Vertex& sampled, int s, int t, const ConnectionDensities& reverse,
                                  const Vertex* merged) {
  // One segment (the camera sees a light): no other technique (BDPT skips
  // s = t = 1, and nothing lies between the two to merge).
  if (s + t == 2) return {1.f, 0.f};
  PhaseScope phase(Phase::Weights);
  Ends e(light, camera, sampled, s, t, merged);
  const Vertex *qs = e.qs, *pt = e.pt, *qsMinus = e.qsMinus, *ptMinus = e.ptMinus;
  const Vertex& y0 = s == 0 ? *pt : s == 1 ? *qs : light[0];
  const Vertex& y1 = s > 1 ? light[1] : s == 1 ? *pt : *ptMinus;
  double nee = s >= 2 ? double(light[0].neeOverEmit) : double(neeOverEmit(scene, y0, y1));
  Terms terms{h, allowed};
  bool zero = false;
  auto rho = [&](double rev, const Vertex& v) {
    zero |= !(v.pdfFwd > 0);
    return heuristic(h, ratio(rev, v.pdfFwd));
  };

  // Camera side, Eq. 4: z_{t-1} is reached from the light subpath, z_{t-2}
  // from z_{t-1} coming from the light side.
  double cameraSide = 0, mergeHere = 0;
  if (t >= 2) {
    double r1 = rho(reverse.pt, *pt);
    // The strategy that connects z_{t-2} and z_{t-1} has s + 1 light
    // vertices: next-event estimation when s = 0, light tracing when t = 2.
    // A merge at z_{t-1} needs it not to be the light's own point (s = 0).
    double a1 = allowed.connections && !ptMinus->delta ? (s == 0 ? heuristic(h, nee) : t == 2 ? 1.0 : terms.count())
                                                       : 0.0;
    double m1 = s > 0 ? terms.merge(*pt, false) : 0.0;
    double inner = 0;
    if (t >= 3) {
      const Vertex& before = camera[size_t(t - 3)];
      zero |= before.misBaseZero;
      inner = rho(reverse.ptMinus, *ptMinus) *
              (terms.camera(*ptMinus, t - 2, ptMinus->delta, before.delta) + before.misSum);
    }
    cameraSide = r1 * (a1 + m1 + inner);
    mergeHere = r1 * m1;
  }

  // Light side, Eq. 5: y_{s-1} is reached from the camera subpath, y_{s-2}
  // from y_{s-1} coming from the camera side (kept as cached for a merge).
  double lightSide = 0;
  if (s >= 1) {
    double r1 = rho(reverse.qs, *qs);
    bool qsDelta = merged ? qs->delta : false;  // a merge's light[s-1] keeps its flag (a caustic's glass)
    bool deltaBefore = s >= 2 ? qsMinus->delta : y0.isDeltaLight();
    double inner = 0;
    if (s >= 2 && merged) {
      inner = qsMinus->misSum;
      zero |= qsMinus->misBaseZero;
    } else if (s >= 2) {
      bool deltaBefore2 = s >= 3 ? light[size_t(s - 3)].delta : light[0].isDeltaLight();
      double rest = 0;
      if (s >= 3) rest = light[size_t(s - 3)].misSum, zero |= light[size_t(s - 3)].misBaseZero;
      inner = rho(reverse.qsMinus, *qsMinus) * (terms.light(*qsMinus, s - 2, qsMinus->delta, deltaBefore2, nee) + rest);
    }
    lightSide = r1 * (terms.light(*qs, s - 1, qsDelta, deltaBefore, nee) + inner);
  }
  if (zero) return {};  // beyond a zero forward density the base itself is impossible

  // The technique's own term, relative to the base (the connection (s, t)
  // with its light endpoint sampled by emission): next-event estimation's
  // ratio for s = 1. A merge's path need not be connectible at (s, t):
  // light[s-1] may be delta.
  double own = 0;
  if (s == 0) own = 1;
  else if (allowed.connections && !(merged && s >= 2 && !qs->connectible()))
    own = s == 1 ? heuristic(h, nee) : t == 1 ? 1.0 : terms.count();
  double total = own + cameraSide + lightSide;
  if (!(total > 0)) return {};
  return {float(own / total), float(mergeHere / total)};
}

}  // namespace lb::bidir
