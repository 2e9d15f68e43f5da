// The O(s+t) ratio walk that mis.h's partial sums replace (pbrt-v3 §16.3.4,
// extended with merges): every weight recomputed from the stored densities
// alone, kept to check the O(1) weights against (verification.h).
#include "integrators/bidirectional/verification.h"

namespace lb::bidir {

namespace {

// Restores a value on scope exit: MIS weights edit a few vertex fields to
// describe the path as the other strategies would have sampled it.
template <typename T>
class Restore {
 public:
  Restore() = default;
  Restore(T* target, T value) : target_(target), saved_(*target) { *target = value; }
  Restore(Restore&& o) noexcept : target_(o.target_), saved_(o.saved_) { o.target_ = nullptr; }
  Restore& operator=(Restore&& o) noexcept {
    std::swap(target_, o.target_), std::swap(saved_, o.saved_);
    return *this;
  }
  ~Restore() {
    if (target_) *target_ = saved_;
  }

 private:
  T* target_ = nullptr;
  T saved_{};
};

// In double: a merge's term (r · p · η)² can pass a float's range on paths
// that merging samples far better than anything else (its weight must then
// be ~1, not Inf/Inf).
double heuristicTerm(MisWeighting h, double r) {
  switch (h) {
    case MisWeighting::Power: return r * r;
    case MisWeighting::Balance: return r;
    default: return r > 0 ? 1.f : 0.f;  // uniform: count every strategy that can sample the path
  }
}

}  // namespace

// MIS weights over every technique that can generate the path (Veach 1997
// Eq. 10.9 and §10.3.5), with the density ratios p_i / p_base built outward
// from the connection (s, t) by multiplying pdfRev / pdfFwd one vertex at a
// time (pbrt-v3 §16.3.4). "base" is the connection (s, t) with its light
// endpoint sampled by emission. Densities follow vertex.h: area measure,
// deltas factored out (so specular chains cancel), roulette excluded. The
// light endpoint needs one correction: strategy s = 1 samples it by
// next-event estimation, every other technique by emission (or, s = 0, not at
// all), so s = 1 carries neeOverEmit = p_NEE / p_emit.
//
// Merging (Georgiev, Křivánek, Davidovič, Slusallek 2012, §4): merging a
// light subpath that reached vertex x with a camera subpath that reached x has
// the density of the connection just before x (x sampled from the camera side)
// times the light subpath's density of x, times η = N π r² (N light subpaths
// per iteration, the acceptance disc π r²). Walking the ratios, a merge at a
// vertex whose connection ratio is r (the connection that samples it from the
// light) is therefore r · pdfFwd(x) · η on the camera side and, on the light
// side, r' · pdfFwd(x) · η with r' the ratio of the connection that samples x
// from the camera. This is the same quantity as Georgiev's technical report
// ("Implementing VCM", 2012) accumulates in dVCM/dVC/dVM, walked over the
// stored vertices instead of carried along the subpaths. A merge needs a
// non-delta surface vertex that is neither the light's nor the camera's own.
TechniqueWeights techniqueWeightsByWalk(const Scene& scene, MisWeighting h, const Techniques& allowed,
                                  std::vector<Vertex>& light, std::vector<Vertex>& camera, const Vertex& sampled, int s,
                                  int t, const Vertex* merged, const std::function<double(int, int)>* factor) {
  // One segment (the camera sees a light): no other technique (BDPT skips
  // s = t = 1, and nothing lies between the two to merge).
  if (s + t == 2) return {1.f, 0.f};
  Vertex* qs = s > 0 ? &light[size_t(s - 1)] : nullptr;
  Vertex* pt = t > 0 ? &camera[size_t(t - 1)] : nullptr;
  Vertex* qsMinus = s > 1 ? &light[size_t(s - 2)] : nullptr;
  Vertex* ptMinus = t > 1 ? &camera[size_t(t - 2)] : nullptr;

  // The freshly sampled endpoint replaces the subpath's own for s = 1 / t = 1
  // (a merge's light subpath keeps its own, emission-sampled, endpoint).
  Restore<Vertex> a1;
  if (s == 1 && !merged) a1 = Restore<Vertex>(qs, sampled);
  else if (t == 1) a1 = Restore<Vertex>(pt, sampled);
  // The connection vertices are connectible, so not delta for this path; a
  // merge's light[s-1] keeps its own flag (a caustic's glass).
  Restore<bool> a2, a3;
  if (pt) a2 = Restore<bool>(&pt->delta, false);
  if (qs && !merged) a3 = Restore<bool>(&qs->delta, false);
  // Reverse densities at and next to the connection, seen from the other side.
  Restore<float> a4, a5, a6, a7;
  if (pt) {
    float fromLight = merged ? merged->pdfFwd
                             : s > 0 ? vertexPdf(scene, *qs, qsMinus, *pt) : pdfLightOrigin(scene, *pt, *ptMinus);
    a4 = Restore<float>(&pt->pdfRev, fromLight);
  }
  if (ptMinus) a5 = Restore<float>(&ptMinus->pdfRev, s > 0 ? vertexPdf(scene, *pt, qs, *ptMinus) : pdfLight(scene, *pt, *ptMinus));
  if (qs) a6 = Restore<float>(&qs->pdfRev, vertexPdf(scene, *pt, ptMinus, *qs));
  if (qsMinus && !merged) a7 = Restore<float>(&qsMinus->pdfRev, vertexPdf(scene, *qs, pt, *qsMinus));

  // The light endpoint y0 and its neighbour on the full path.
  const Vertex& y0 = s > 0 ? light[0] : *pt;
  const Vertex& y1 = s > 1 ? light[1] : (s == 1 ? *pt : *ptMinus);
  float pEmit = pdfLightOrigin(scene, y0, y1);
  float neeOverEmit = pEmit > 0 ? pdfLightNee(scene, y0, y1) / pEmit : 0.f;
  // A connection s' ≥ 1 competes only where connections are allowed; s' = 0
  // (a camera subpath that hits the light) always does.
  // Its density counts Techniques::connectionCount times when both sides
  // have two or more vertices (a light-vertex-cache draw).
  auto connection = [&](double r, int sOther) {
    if (sOther >= 1 && !allowed.connections) return 0.0;
    int tOther = s + t - sOther;
    if (sOther == 1) r *= neeOverEmit;
    else if (sOther >= 2 && tOther >= 2) r *= allowed.connectionCount;
    if (factor) r *= (*factor)(sOther, tOther);
    return heuristicTerm(h, r);
  };
  auto merge = [&](double r, const Vertex& v) {
    return allowed.mergeEta > 0 ? heuristicTerm(h, r * v.pdfFwd * allowed.mergeEta) : 0.0;
  };
  auto mergeable = [](const Vertex& v) { return v.type == VertexType::Surface && !v.delta && v.connectible(); };
  // Beyond a zero forward density the base itself is impossible: weights 0.
  bool baseZero = false;
  auto ratio = [&](double rev, double fwd) {
    baseZero |= !(fwd > 0);
    return fwd > 0 ? rev / fwd : 0.0;
  };

  TechniqueWeights w;
  // A merge's path need not be connectible at (s, t): light[s-1] may be delta.
  // (s = 1 is next-event estimation, which samples the light itself: the
  // factor neeOverEmit already says whether it can, e.g. for a directional
  // light, whose own vertex is not "connectible".)
  double own = merged && s >= 2 && !qs->connectible() ? 0.0 : connection(1, s);
  double sum = 0, mergeHere = 0, r = 1;
  // Camera side: moving the connection one vertex towards the camera gives
  // strategy s' = s + t - i, which connects camera[i - 1] and camera[i];
  // camera[i] is then reached from both sides, and can be merged.
  for (int i = t - 1; i > 0; --i) {
    const Vertex& v = camera[size_t(i)];
    r *= ratio(v.pdfRev, v.pdfFwd);
    if (!v.delta && !camera[size_t(i - 1)].delta) sum += connection(r, s + t - i);
    bool isLightOrigin = s == 0 && i == t - 1;
    if (mergeable(v) && !isLightOrigin) {
      double m = merge(r, v);
      sum += m;
      if (i == t - 1) mergeHere = m;
    }
  }
  // Light side: strategy s' = i connects light[i - 1] and light[i]; s' = 0
  // needs a light that rays can hit. light[i] (i ≥ 1) can be merged.
  r = 1;
  for (int i = s - 1; i >= 0; --i) {
    const Vertex& v = light[size_t(i)];
    r *= ratio(v.pdfRev, v.pdfFwd);
    bool deltaBefore = i > 0 ? light[size_t(i - 1)].delta : light[0].isDeltaLight();
    if (!v.delta && !deltaBefore) sum += connection(r, i);
    if (i > 0 && mergeable(v)) sum += merge(r, v);
  }
  if (baseZero) return {};
  // With the NEE endpoint own (BDPT's s = 1), the base is emission-sampled
  // but the technique is not: own = h(neeOverEmit), so a zero NEE density
  // gives weight 0.
  double total = own + sum;
  if (!(total > 0)) return {};
  w.connection = float(own / total);
  w.mergeAtCamera = float(mergeHere / total);
  return w;
}

}  // namespace lb::bidir
