#include "integrators/bidirectional/verification.h"

namespace lb::bidir {

namespace {
// Area density of sampling `next` from v (arrived from prev). At a delta
// vertex the BSDF has no density to evaluate; its discrete lobe probability
// (vertex.h) is found by sampling both lobes and keeping the one that leaves
// towards `next`.
// `reverse`: v's successor on the subpath is `prev`, so through a refraction
// the density carries the Jacobian of the direction v sampled (vertex.h).
float densityTowards(const Scene& scene, const Vertex& v, const Vertex* prev, const Vertex& next, bool reverse) {
  if (!(v.type == VertexType::Surface && v.si.material && v.si.material->isDelta()))
    return vertexPdf(scene, v, prev, next);
  BSDF bsdf(v.si);
  Vec3 wo = prev ? glm::normalize(prev->p - v.p) : v.si.wo, wn = glm::normalize(next.p - v.p);
  float best = -1, pdf = 0;
  for (float uLobe : {0.f, 0.999999f})
    if (auto bs = bsdf.sample(wo, uLobe, Vec2(0.5f), TransportMode::Radiance))
      if (float c = glm::dot(bs->wi, wn); c > best) best = c, pdf = bs->pdf;
  if (reverse) pdf *= refractionJacobian(v.si, wn, wo);
  return convertDensity(v, pdf, next);
}

// Re-derives pdfFwd / pdfRev along one subpath (vertex 0 = its origin).
void recompute(const Scene& scene, std::vector<Vertex>& sub, bool lightPath) {
  size_t n = sub.size();
  for (size_t i = 0; i < n; ++i) {
    Vertex& v = sub[i];
    if (i == 0) v.pdfFwd = lightPath ? pdfLightOrigin(scene, v, n > 1 ? sub[1] : v) : 0.f;
    else if (i == 1 && lightPath) v.pdfFwd = pdfLight(scene, sub[0], v);
    else v.pdfFwd = densityTowards(scene, sub[i - 1], i >= 2 ? &sub[i - 2] : nullptr, v, false);
    v.pdfRev = i + 1 < n ? densityTowards(scene, sub[i + 1], i + 2 < n ? &sub[i + 2] : nullptr, v, true) : 0.f;
  }
}

void orient(std::vector<Vertex>& sub) {  // wo of each surface vertex points back along its subpath
  for (size_t i = 1; i < sub.size(); ++i)
    if (sub[i].type == VertexType::Surface) sub[i].si.wo = glm::normalize(sub[i - 1].p - sub[i].p);
}
}  // namespace

std::vector<PdfMismatch> checkSubpathPdfs(const Scene& scene, const std::vector<Vertex>& path, int n, bool lightPath) {
  std::vector<Vertex> fresh(path.begin(), path.begin() + n);
  recompute(scene, fresh, lightPath);
  std::vector<PdfMismatch> out;
  for (int i = 0; i < n; ++i) {
    if (i >= 1 && !(i == 1 && lightPath && path[0].infinite)) out.push_back({i, false, path[size_t(i)].pdfFwd, fresh[size_t(i)].pdfFwd});
    // pdfRev of vertex n-2 is set only if the walk sampled a direction at the
    // last vertex; the MIS recursion always overwrites it at a connection
    // (it is ptMinus / qsMinus there), so it is not compared.
    if (i + 2 < n) out.push_back({i, true, path[size_t(i)].pdfRev, fresh[size_t(i)].pdfRev});
  }
  return out;
}

std::vector<float> strategyWeights(const Scene& scene, MisWeighting h, const std::vector<Vertex>& full) {
  int n = int(full.size());
  std::vector<float> weights;
  const Vertex& end = full.back();
  for (int s = 0; s < n; ++s) {
    int t = n - s;
    std::vector<Vertex> camera(full.begin(), full.begin() + t), light;
    for (int i = n - 1; i >= t; --i) light.push_back(full[size_t(i)]);
    if (!light.empty() && light[0].type == VertexType::Surface) {
      // The emitting surface as a light subpath's origin.
      Vertex l = lightVertex(light[0].si.emitter, light[0].p, light[0].ng, light[0].pError, Color(1.f), 0);
      light[0] = l;
    }
    orient(camera), orient(light);
    for (auto& v : camera) v.delta = v.type == VertexType::Surface && v.si.material && v.si.material->isDelta();
    for (auto& v : light) v.delta = v.type == VertexType::Surface && v.si.material && v.si.material->isDelta();
    recompute(scene, camera, false);
    recompute(scene, light, true);
    bool possible;
    if (s == 0) possible = end.isLight() && !(end.type == VertexType::Light && end.light && end.light->isDelta());
    else
      possible = camera.back().connectible() && !camera.back().delta &&
                 (s == 1 || (light.back().connectible() && !light.back().delta));  // s = 1 samples the light itself
    if (s == 1 && t == 1) possible = false;  // never used (pbrt-v3): s = 0, t = 2 covers it
    if (!possible) {
      weights.push_back(-1);
      continue;
    }
    computePartialSums(scene, h, Techniques{}, camera, int(camera.size()), SubpathSide::Camera);
    computePartialSums(scene, h, Techniques{}, light, int(light.size()), SubpathSide::Light);
    Vertex sampled;
    if (s == 1) sampled = light[0];
    if (t == 1) sampled = camera[0];
    weights.push_back(misWeight(scene, h, light, camera, sampled, s, t));
  }
  return weights;
}

}  // namespace lb::bidir
