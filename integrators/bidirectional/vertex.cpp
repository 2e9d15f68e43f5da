#include "integrators/bidirectional/vertex.h"

namespace lb::bidir {

bool Vertex::connectible() const {
  switch (type) {
    case VertexType::Camera: return true;
    case VertexType::Light: return !(infinite && light && light->isDelta());  // not a delta direction
    case VertexType::Surface: return si.material && !si.material->isDelta();
  }
  return false;
}

Vertex cameraVertex(const Camera& camera, const Color& beta) {
  Vertex v;
  v.type = VertexType::Camera;
  v.p = camera.position();
  v.beta = beta;
  return v;
}

Vertex lightVertex(const Light* light, const Vec3& p, const Vec3& n, const Vec3& pError, const Color& beta, float pdf) {
  Vertex v;
  v.type = VertexType::Light;
  v.light = light;
  v.p = p, v.ng = n, v.pError = pError;
  v.beta = beta;
  v.pdfFwd = pdf;
  v.infinite = light->isInfinite();
  return v;
}

Vertex surfaceVertex(const SurfaceInteraction& si, const Color& beta) {
  Vertex v;
  v.type = VertexType::Surface;
  v.si = si;
  v.p = si.p, v.ng = si.ng, v.pError = si.pError;
  v.beta = beta;
  return v;
}

Vertex escapedVertex(const Ray& ray, const Color& beta, float pdfSolidAngle) {
  Vertex v;
  v.type = VertexType::Light;
  v.infinite = true;
  v.escapeDir = ray.d;
  v.p = ray.o + ray.d;  // a point along the escape direction (only directions matter)
  v.beta = beta;
  v.pdfFwd = pdfSolidAngle;
  return v;
}

float refractionJacobian(const SurfaceInteraction& si, const Vec3& wo, const Vec3& wi) {
  const Vec3& n = si.shading.n;
  float cosO = glm::dot(wo, n), cosI = glm::dot(wi, n);
  if (cosO * cosI >= 0 || !si.material) return 1;  // same side: a reflection
  float eta = si.material->relativeEta(si.shading.toLocal(wo));  // η_wi / η_wo
  return std::abs(cosO) / (eta * eta * std::abs(cosI));
}

float reverseDirectionalDensity(const SurfaceInteraction& si, const ScatterSample& bs) {
  return bs.isDelta() ? bs.pdfRev * refractionJacobian(si, si.wo, bs.wi) : bs.pdfRev;
}

float convertDensity(const Vertex& from, float pdf, const Vertex& to) {
  if (to.isInfiniteLight()) return pdf;  // densities at infinity stay per solid angle
  Vec3 w = to.p - from.p;
  float d2 = glm::dot(w, w);
  if (d2 == 0) return 0;
  if (to.onSurface()) pdf *= absDot(to.ng, w / std::sqrt(d2));
  return pdf / d2;
}

namespace {
Vec3 direction(const Vertex& from, const Vertex& to) {
  if (to.isInfiniteLight() && to.type == VertexType::Light && !to.light) return to.escapeDir;
  return glm::normalize(to.p - from.p);
}
}  // namespace

Color vertexF(const Vertex& v, const Vertex& next, TransportMode mode) {
  if (v.type != VertexType::Surface || !v.si.material) return Color(0.f);
  return BSDF(v.si).eval(v.si.wo, direction(v, next), mode).f;
}

float vertexPdf(const Scene& scene, const Vertex& v, const Vertex* prev, const Vertex& next) {
  if (v.type == VertexType::Light) return pdfLight(scene, v, next);
  Vec3 wn = direction(v, next);
  float pdf;
  if (v.type == VertexType::Camera) {
    float pdfPos;
    scene.camera.pdfWe(wn, &pdfPos, &pdf);
  } else {
    if (!v.si.material) return 0;
    Vec3 wp = prev ? glm::normalize(prev->p - v.p) : v.si.wo;
    pdf = BSDF(v.si).pdf(wp, wn);
  }
  return convertDensity(v, pdf, next);
}

float pdfLight(const Scene& scene, const Vertex& v, const Vertex& to) {
  Vec3 w = to.p - v.p;
  float d2 = glm::dot(w, w);
  if (v.isInfiniteLight() && !v.light) w = -v.escapeDir, d2 = 1;  // escaped ray: only its direction exists
  if (d2 == 0) return 0;
  w /= std::sqrt(d2);
  float pdf;
  if (v.isInfiniteLight()) {
    // Emission from infinity starts on a disc covering the scene: its density
    // per area is what reaches `to` (no 1/r²).
    const Light* any = v.light ? v.light : (scene.infiniteLights().empty() ? nullptr : scene.infiniteLights()[0]);
    if (!any) return 0;
    float pdfPos, pdfDir;
    any->pdfLe(v.p, Vec3(0.f), -w, &pdfPos, &pdfDir);
    pdf = pdfPos;
  } else {
    const Light* light = v.emitter();
    if (!light) return 0;
    float pdfPos, pdfDir;
    light->pdfLe(v.p, v.ng, w, &pdfPos, &pdfDir);
    pdf = pdfDir / d2;
  }
  if (to.onSurface()) pdf *= absDot(to.ng, w);
  return pdf;
}

float pdfLightOrigin(const Scene& scene, const Vertex& v, const Vertex& to) {
  Vec3 w = v.isInfiniteLight() && !v.light ? -v.escapeDir : glm::normalize(to.p - v.p);
  const LightSampler& lights = scene.lightSampler();
  // Delta lights: the position (or direction) is a delta common to every
  // strategy that can use them; only the choice of the light remains.
  if (v.isDeltaLight()) return lights.pmf(v.light);
  if (v.isInfiniteLight()) {
    // Any infinite light could have been chosen: sum their solid-angle pdfs
    // of the direction from `to` towards infinity.
    float pdf = 0;
    for (const Light* l : scene.infiniteLights()) pdf += lights.pmf(l) * l->pdfLi(to.p, -w, v.p, Vec3(0.f));
    return pdf;
  }
  const Light* light = v.emitter();
  if (!light) return 0;
  float pdfPos, pdfDir;
  light->pdfLe(v.p, v.ng, w, &pdfPos, &pdfDir);
  return lights.pmf(light) * pdfPos;
}

float pdfLightNee(const Scene& scene, const Vertex& v, const Vertex& ref) {
  const Light* light = v.emitter();
  if (v.isInfiniteLight() || v.isDeltaLight()) return pdfLightOrigin(scene, v, ref);  // same sampling both ways
  if (!light) return 0;
  Vec3 d = v.p - ref.p;
  float d2 = glm::dot(d, d);
  if (d2 == 0) return 0;
  Vec3 wi = d / std::sqrt(d2);
  // sampleLi's solid-angle density at ref, as an area density at v.
  return scene.lightSampler().pmf(light) * light->pdfLi(ref.p, wi, v.p, v.ng) * absDot(v.ng, wi) / d2;
}

Color emitted(const Scene& scene, const Vertex& v, const Vertex& to) {
  if (v.isInfiniteLight() && !v.light) {
    Color L(0.f);
    for (const Light* l : scene.infiniteLights()) L += l->Le(v.escapeDir);
    return L;
  }
  const Light* light = v.emitter();
  if (!light) return Color(0.f);
  return light->L(v.ng, glm::normalize(to.p - v.p));
}

}  // namespace lb::bidir
