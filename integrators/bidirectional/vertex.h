#pragma once
// Path vertices of bidirectional path tracing and their densities, following
// Veach 1997 ch. 10 and pbrt-v3/v4 (§16.3). Conventions:
//  * pdfFwd: density of generating this vertex from its predecessor on its own
//    subpath; pdfRev: density of generating it from its successor, i.e. when
//    the path is sampled from the other end. Both are per unit AREA (per solid
//    angle for vertices at infinity, which have no area).
//  * A delta lobe (mirror, glass) samples its direction with a discrete
//    probability P, the same in both directions (Fresnel is symmetric). Its
//    "density" is kept as P per unit solid angle, i.e. the delta itself is
//    factored out (Veach 1997 §8.2.2): every strategy that can generate a path
//    passes through the same specular vertices by sampling and carries the
//    same deltas, which cancel in the ratios. The neighbours' area densities
//    keep their |cos|/d² conversions, so a specular chain's generalised
//    geometry term appears in every strategy and cancels too. (pbrt-v3 stored
//    0 here and read it as 1, dropping those conversions: through a chain
//    L S S D E that over-weights the camera strategy by d01²/d23²·… — ~100×
//    on a caustic.) Strategies that would connect at a delta vertex are
//    skipped.
//  * Except through refraction: the delta of a refracting vertex is a delta
//    in the direction it sampled, and the strategies that cross the vertex
//    the other way carry the delta of the other side, which differs by the
//    refraction map's Jacobian (Veach 1997 §5.2, étendue η² cos θ dω kept):
//        δ(ω_o − T(ω_i)) = δ(ω_i − T⁻¹(ω_o)) / |dω_o/dω_i|,
//        |dω_o/dω_i| = (η_i² cos θ_i) / (η_o² cos θ_o)   (shading-normal cosines).
//    So a reverse density through a smooth refraction is P · |dω_wi/dω_wo|
//    (the walk's own wo, wi), its forward density P. Through a sphere the
//    two interfaces' factors cancel on symmetric chords, which is why SmallVCM
//    and pbrt drop them; through one flat interface (a water surface, a light
//    under glass) they do not (up to ~1.8× at normal incidence for water's
//    η² and without bound near grazing).
//  * The light endpoint has two densities: emission sampling's (pdfFwd of a
//    light subpath's first vertex) and next-event estimation's (s = 1, which
//    samples a sphere's cone, not its area); misWeight uses each where it
//    belongs.
//  * Russian roulette does not enter these pdfs: the weights of all strategies
//    that can generate a path still sum to 1, which keeps every estimator
//    unbiased (references.md, "BDPT bookkeeping"); roulette only reweights β.
#include <vector>
#include "core/bsdfs/bsdf.h"
#include "core/scene.h"

namespace lb::bidir {

enum class VertexType { Camera, Light, Surface };

struct Vertex {
  VertexType type = VertexType::Surface;
  Color beta{0.f};        // throughput of the subpath up to and including this vertex
  bool delta = false;     // sampled a delta lobe here (cannot be connected to)
  bool regularized = false;  // si.material is a delta material's rough twin (core/bsdfs/regularization.h)
  float pdfFwd = 0, pdfRev = 0;
  Vec3 p{0.f}, ng{0.f}, pError{0.f};
  SurfaceInteraction si;  // Surface vertices
  const Light* light = nullptr;  // Light vertices (null for an escaped camera ray)
  bool infinite = false;  // a light at infinity (environment, directional) or an escaped ray
  Vec3 escapeDir{0.f};    // escaped camera ray: its direction
  // MIS partial sums (mis.h, Eq. 3), filled by computePartialSums.
  double misSum = 0;         // S_k: every technique connecting or merging at or before this vertex
  bool misBaseZero = false;  // a zero forward density at or before this vertex
  float neeOverEmit = 0;     // light subpath's y0 only: p_NEE(y0) / p_emit(y0) towards y1

  bool onSurface() const { return type == VertexType::Surface || (type == VertexType::Light && glm::dot(ng, ng) > 0); }
  bool isLight() const { return type == VertexType::Light || (type == VertexType::Surface && si.emitter); }
  bool isDeltaLight() const { return type == VertexType::Light && light && light->isDelta(); }
  bool isInfiniteLight() const { return type == VertexType::Light && infinite; }
  bool connectible() const;
  // A vertex photons can be merged at (VCM, BPM, PPM): a non-specular
  // surface, not a light's own point.
  bool mergeable() const { return type == VertexType::Surface && connectible(); }
  const Light* emitter() const { return type == VertexType::Light ? light : si.emitter; }
  Vec3 shadingNormal() const { return si.shading.n; }
};

// A subpath's vertices wherever they are stored: a vector of its own, or a
// range of an iteration's light vertices (VCM keeps them in one array per
// tile). Read-only: the MIS weights never edit a vertex (mis.h).
class Subpath {
 public:
  Subpath(const std::vector<Vertex>& v) : data_(v.data()), size_(v.size()) {}  // NOLINT: implicit by design
  Subpath(const Vertex* data, size_t size) : data_(data), size_(size) {}
  const Vertex& operator[](size_t i) const { return data_[i]; }
  size_t size() const { return size_; }

 private:
  const Vertex* data_;
  size_t size_;
};

Vertex cameraVertex(const Camera& camera, const Color& beta);
Vertex lightVertex(const Light* light, const Vec3& p, const Vec3& n, const Vec3& pError, const Color& beta, float pdf);
Vertex surfaceVertex(const SurfaceInteraction& si, const Color& beta);
Vertex escapedVertex(const Ray& ray, const Color& beta, float pdfSolidAngle);

// |dω_wi / dω_wo| at a smooth refracting vertex crossed from wo towards wi,
// 1 for a reflection (and for thin glass, which does not bend the ray).
float refractionJacobian(const SurfaceInteraction& si, const Vec3& wo, const Vec3& wi);
// The directional density of sampling bs's wo from its wi, in the measure of
// the delta bs sampled: bs.pdfRev, times refractionJacobian for a delta lobe.
float reverseDirectionalDensity(const SurfaceInteraction& si, const ScatterSample& bs);
// Converts a solid-angle density at `from` towards `to` into area density at `to`.
float convertDensity(const Vertex& from, float pdf, const Vertex& to);
// BSDF (or camera) value at v for the directions to prev (where the subpath came
// from) and next; f includes the adjoint correction in importance mode.
Color vertexF(const Vertex& v, const Vertex& next, TransportMode mode);
// Area density of sampling `next` from v, having arrived from `prev`.
float vertexPdf(const Scene& scene, const Vertex& v, const Vertex* prev, const Vertex& next);
// Area density of light vertex (or emitting surface) v emitting towards `to`.
float pdfLight(const Scene& scene, const Vertex& v, const Vertex& to);
// Density of choosing v's light and sampling v on it by emission sampling
// (area; solid angle at infinity; the selection probability alone for delta
// lights, whose position is a delta shared by every strategy that can use them).
float pdfLightOrigin(const Scene& scene, const Vertex& v, const Vertex& to);
// Density of the same light point sampled by next-event estimation from `ref`
// (sampleLi: spheres sample their cone, not their area), in the same measure.
float pdfLightNee(const Scene& scene, const Vertex& v, const Vertex& ref);
// Radiance emitted from v towards `to` (area light surface or escaped ray).
Color emitted(const Scene& scene, const Vertex& v, const Vertex& to);

}  // namespace lb::bidir
