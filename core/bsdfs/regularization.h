#pragma once
// Path-space regularization (Kaplanyan & Dachsbacher 2013, "Path Space
// Regularization for Holistic and Robust Light Transport"), for the path
// tracer (`path`), BDPT (`bdpt`) and VCM (`vcm`), with `regularize: true`.
//
// A path tracer cannot complete a path whose light reaches a diffuse vertex
// only through a specular one (L S D … E: the floor of a pool under a small
// sun, seen through the water): next-event estimation from the diffuse
// vertex is blocked by the specular surface, and a BSDF-sampled direction
// through it must hit the light by chance (never, for a point light). BDPT
// fares no better with L S D S E: every connection would end at a specular
// vertex. The paper's remedy is to mollify such a specular interaction: its
// delta BSDF is replaced by a narrow smooth lobe, so the vertex can be
// connected to (a light sample, or a light subpath).
//
// Where: a delta vertex with a non-delta vertex somewhere between it and the
// camera (the paper's condition for L S D S E; a specular surface the camera
// reaches before any diffuse one is kept exact). This is a property of the
// path, not of how it was sampled, so every strategy of BDPT integrates the
// same regularized contribution and MIS combines them as usual:
//  * a camera walk regularizes a delta vertex after its first non-delta one
//    (what the path tracer does);
//  * a light walk regularizes every delta vertex, since any connection with
//    t >= 2 ends at a camera vertex that is non-delta or comes after one;
//  * so the one strategy that may not use a regularized vertex is t = 1
//    (connecting the light subpath's end to the camera): that vertex has
//    nothing between it and the camera, so it must be non-delta as it is;
//  * a merge (VCM) evaluates the camera vertex's BSDF only, at a vertex that
//    is non-delta or a twin: either way a non-delta vertex lies on the
//    camera's side, so the light subpath's twins are the rule's.
// Paths without such a vertex are computed exactly as without
// regularization; those with one are paths of a slightly different scene,
// so the image is biased for them.
//
// How: the delta material's rough twin (Material::mollified: GGX glass or
// metal of roughness α with the same IOR or Fresnel), here in place of the
// paper's cone kernel, as issue 36 asks ("a microfacet lobe").
//
// Schedule (the paper's consistency condition, §5.1): the bandwidth of pass
// k (k = 0, 1, …) is α_k = α_0 · (k + 1)^(−λ) with 0 < λ < 1/d (d = 2
// dimensions mollified per vertex); the bias of pass k shrinks with α_k
// (O(α_k²) where the integrand is smooth), its variance grows at most like
// 1/α_k², so the average of N passes has bias → 0 and variance
// O(N^(2λ−1)) → 0. λ = 1/6 balances the two (MSE-optimal for one vertex);
// λ = 0 keeps α fixed (a biased study of one bandwidth, not consistent).
#include <cstdint>
#include <memory>
#include <unordered_map>
#include "core/params.h"
#include "core/scene.h"

namespace lb {

struct RegularizationSettings {
  // regularize, and with it regularize_roughness and regularize_exponent.
  static RegularizationSettings read(Params& p);
  bool enabled = false;
  float initialRoughness = 0.1f;  // α_0
  float exponent = 1.f / 6.f;     // λ
  // α_k of pass k (0-based).
  float roughness(uint64_t pass) const;
};

// The scene's delta materials' rough twins for one pass's α_k.
class Regularization {
 public:
  explicit Regularization(RegularizationSettings s) : settings_(s) {}
  // Makes the twins for pass `pass` (between passes: the map is read-only while a pass renders).
  void prepare(const Scene& scene, uint64_t pass);
  // The twin of `material`, or null where it has none.
  const Material* twin(const Material* material) const {
    auto it = twins_.find(material);
    return it == twins_.end() ? nullptr : it->second.get();
  }
  float roughness() const { return roughness_; }

 private:
  RegularizationSettings settings_;
  float roughness_ = 0;
  std::unordered_map<const Material*, std::unique_ptr<Material>> twins_;
};

}  // namespace lb
