#include "tests/support/path_pdfs.h"
#include <cmath>

namespace lb::test {

using bidir::MisWeighting;

namespace {

using bidir::Vertex;
using bidir::VertexType;
using DVec3 = glm::dvec3;

DVec3 d3(const Vec3& v) { return DVec3(v); }
bool escaped(const Vertex& v) { return v.type == VertexType::Light && v.infinite && !v.light; }
bool atInfinity(const Vertex& v) { return v.type == VertexType::Light && v.infinite; }
bool onSurface(const Vertex& v) {
  return v.type == VertexType::Surface || (v.type == VertexType::Light && glm::dot(v.ng, v.ng) > 0);
}
bool specular(const Vertex& v) { return v.type == VertexType::Surface && v.si.material && v.si.material->isDelta(); }
const Light* emitterOf(const Vertex& v) { return v.type == VertexType::Light ? v.light : v.si.emitter; }
bool deltaLight(const Vertex& v) {
  const Light* l = emitterOf(v);
  return l && l->isDelta();
}

// Unit direction from a to b; a vertex at infinity is a direction, not a point.
DVec3 direction(const Vertex& a, const Vertex& b) {
  if (escaped(b)) return d3(b.escapeDir);
  if (escaped(a)) return -d3(a.escapeDir);
  return glm::normalize(d3(b.p) - d3(a.p));
}

// Solid angle at a → area at b: |cos θ_b| / d²; nothing at infinity.
double toArea(const Vertex& a, const Vertex& b) {
  if (atInfinity(b)) return 1;
  DVec3 d = d3(b.p) - d3(a.p);
  double d2 = glm::dot(d, d);
  double cos = onSurface(b) ? std::abs(glm::dot(d3(b.ng), d / std::sqrt(d2))) : 1.0;
  return cos / d2;
}

// Solid-angle density with which v (reached from prev) samples the direction
// to next: the camera's, or the BSDF's; a specular lobe's delta counts as 1.
double directional(const Scene& scene, const Vertex* prev, const Vertex& v, const Vertex& next) {
  Vec3 w = Vec3(direction(v, next));
  if (v.type == VertexType::Camera) {
    float pos, dir;
    scene.camera.pdfWe(w, &pos, &dir);
    return dir;
  }
  if (specular(v)) return 1;
  return BSDF(v.si).pdf(Vec3(direction(v, *prev)), w);
}

// Light-selection probability times the emission density of the light end
// y0: position (area) for finite lights, direction (solid angle) at infinity.
double emissionOrigin(const Scene& scene, const Vertex& y0, const Vertex& y1) {
  const LightSampler& sampler = scene.lightSampler();
  if (deltaLight(y0)) return sampler.pmf(emitterOf(y0));
  float pos, dir;
  if (atInfinity(y0)) {  // any infinite light could have emitted this direction
    double sum = 0;
    for (const Light* l : scene.infiniteLights()) {
      if (l->isDelta()) continue;
      l->pdfLe(Vec3(0.f), Vec3(0.f), Vec3(direction(y0, y1)), &pos, &dir);
      sum += sampler.pmf(l) * dir;
    }
    return sum;
  }
  const Light* l = emitterOf(y0);
  l->pdfLe(y0.p, y0.ng, Vec3(direction(y0, y1)), &pos, &dir);
  return sampler.pmf(l) * pos;
}

// Density of y1 given y0 under emission sampling.
double emissionNext(const Scene& scene, const Vertex& y0, const Vertex& y1) {
  float pos, dir;
  Vec3 w = Vec3(direction(y0, y1));
  if (atInfinity(y0)) {
    // From infinity: a point on a disc perpendicular to the direction, whose
    // area density becomes |cos θ_y1| times it on the surface.
    const Light* l = emitterOf(y0) ? emitterOf(y0) : scene.infiniteLights().front();
    l->pdfLe(Vec3(0.f), Vec3(0.f), w, &pos, &dir);
    return pos * (onSurface(y1) ? std::abs(glm::dot(d3(y1.ng), d3(w))) : 1.0);
  }
  emitterOf(y0)->pdfLe(y0.p, y0.ng, w, &pos, &dir);
  return dir * toArea(y0, y1);
}

// Density of y0 under next-event estimation from ref.
double neeOrigin(const Scene& scene, const Vertex& y0, const Vertex& ref) {
  const LightSampler& sampler = scene.lightSampler();
  if (deltaLight(y0)) return sampler.pmf(emitterOf(y0));
  Vec3 wi = Vec3(direction(ref, y0));
  if (atInfinity(y0)) {
    double sum = 0;
    for (const Light* l : scene.infiniteLights())
      if (!l->isDelta()) sum += sampler.pmf(l) * l->pdfLi(ref.p, wi, y0.p, Vec3(0.f));
    return sum;
  }
  const Light* l = emitterOf(y0);
  return sampler.pmf(l) * l->pdfLi(ref.p, wi, y0.p, y0.ng) * toArea(ref, y0);
}

// A specular vertex x_k sampled from the light side (arrived from x_{k+1},
// sampled towards x_{k-1}) carries a delta in the direction towards x_{k-1};
// the strategies that sample it from the camera side carry one towards
// x_{k+1}. Measured in the camera side's delta, the light side's density is
// P · |dω_{k+1} / dω_{k-1}|, and étendue (η² cos θ dω) is conserved through a
// refraction: |dω_{k+1} / dω_{k-1}| = η_{k-1}² cos θ_{k-1} / (η_{k+1}² cos θ_{k+1}),
// cosines against the shading normal, and η_{k-1} / η_{k+1} measured by
// Snell's law on the material's own refraction of a 20° direction from the
// side of x_{k-1} (sin θ_t / sin θ_i), not read from the material's
// parameters: an oracle that took η where the code does would share its
// mistakes. A reflection: 1.
double lightSideDelta(const Vertex& towardsCamera, const Vertex& v, const Vertex& towardsLight) {
  DVec3 a = direction(v, towardsCamera), b = direction(v, towardsLight);
  DVec3 ns = d3(v.si.shading.n);
  double cosA = glm::dot(a, ns), cosB = glm::dot(b, ns);
  if (cosA * cosB >= 0) return 1;
  // 20° from the normal, on a's side in the local frame: short of total
  // internal reflection from the denser side for any η below 2.9.
  Vec3 probe(std::sin(0.35f), 0, cosA > 0 ? std::cos(0.35f) : -std::cos(0.35f));
  double etaRatio = 0;  // η_a / η_b
  for (float uLobe : {0.f, 0.5f, 0.999999f})
    if (auto s = v.si.material->sample(probe, uLobe, Vec2(0.5f), TransportMode::Radiance))
      if (s->wi.z * probe.z < 0) etaRatio = std::sqrt(1 - sqr(double(s->wi.z))) / std::sqrt(1 - sqr(double(probe.z)));
  return sqr(etaRatio) * std::abs(cosA) / std::abs(cosB);
}

// The product of lightSideDelta over the specular vertices path[k], k >= first
// (the ones a strategy whose camera subpath ends before `first` samples from the light).
double lightSideDeltas(const std::vector<Vertex>& path, int first) {
  double f = 1;
  for (int k = std::max(first, 1); k + 1 < int(path.size()); ++k)
    if (specular(path[size_t(k)])) f *= lightSideDelta(path[size_t(k - 1)], path[size_t(k)], path[size_t(k + 1)]);
  return f;
}

bool strategyPossible(const std::vector<Vertex>& path, int s) {
  int n = int(path.size()), t = n - s;
  const Vertex& end = path.back();
  if (s == 0) return escaped(end) || (emitterOf(end) && !deltaLight(end));  // a light rays can hit
  if (s == 1 && t == 1) return false;
  const Vertex &z = path[size_t(t - 1)], &y = path[size_t(t)];
  bool zOk = z.type == VertexType::Camera || (z.type == VertexType::Surface && !specular(z));
  bool yOk = s == 1 || (y.type == VertexType::Surface && !specular(y));
  return zOk && yOk;
}

}  // namespace

std::vector<double> strategyPdfsFromDefinition(const Scene& scene, const std::vector<Vertex>& path) {
  int n = int(path.size());
  std::vector<double> pdfs(size_t(n), 0.0);
  for (int s = 0; s < n; ++s) {
    if (!strategyPossible(path, s)) continue;
    int t = n - s;
    double p = 1;
    // Camera subpath z0…z(t-1) = path[0…t-1].
    for (int j = 1; j < t; ++j)
      p *= directional(scene, j >= 2 ? &path[size_t(j - 2)] : nullptr, path[size_t(j - 1)], path[size_t(j)]) *
           toArea(path[size_t(j - 1)], path[size_t(j)]);
    // Light subpath y0…y(s-1) = path[n-1], path[n-2], …
    auto y = [&](int i) -> const Vertex& { return path[size_t(n - 1 - i)]; };
    if (s == 1) p *= neeOrigin(scene, y(0), path[size_t(t - 1)]);
    if (s >= 2) p *= emissionOrigin(scene, y(0), y(1)) * emissionNext(scene, y(0), y(1));
    for (int i = 2; i < s; ++i) p *= directional(scene, &y(i - 2), y(i - 1), y(i)) * toArea(y(i - 1), y(i));
    pdfs[size_t(s)] = p * lightSideDeltas(path, t);
  }
  return pdfs;
}

std::vector<double> mergePdfsFromDefinition(const Scene& scene, const std::vector<Vertex>& path, double eta) {
  int n = int(path.size());
  std::vector<double> pdfs(size_t(n), 0.0);
  auto y = [&](int i) -> const Vertex& { return path[size_t(n - 1 - i)]; };
  for (int k = 1; k <= n - 2; ++k) {
    const Vertex& x = path[size_t(k)];
    if (x.type != VertexType::Surface || specular(x)) continue;
    double p = eta;
    for (int j = 1; j <= k; ++j)  // camera subpath z0…zk
      p *= directional(scene, j >= 2 ? &path[size_t(j - 2)] : nullptr, path[size_t(j - 1)], path[size_t(j)]) *
           toArea(path[size_t(j - 1)], path[size_t(j)]);
    int s = n - k;  // light subpath y0…y(s-1) = path[n-1] … path[k], emission-sampled
    p *= emissionOrigin(scene, y(0), y(1)) * emissionNext(scene, y(0), y(1));
    for (int i = 2; i < s; ++i) p *= directional(scene, &y(i - 2), y(i - 1), y(i)) * toArea(y(i - 1), y(i));
    pdfs[size_t(k)] = p * lightSideDeltas(path, k + 1);
  }
  return pdfs;
}

std::vector<double> weightsFromPdfs(const std::vector<double>& pdfs, MisWeighting h) {
  auto term = [h](double p) { return h == MisWeighting::Power ? p * p : h == MisWeighting::Balance ? p : (p > 0 ? 1.0 : 0.0); };
  double sum = 0;
  for (double p : pdfs) sum += term(p);
  std::vector<double> w;
  for (double p : pdfs) w.push_back(sum > 0 ? term(p) / sum : 0.0);
  return w;
}

}  // namespace lb::test
