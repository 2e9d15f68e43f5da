#pragma once
// Plastic: a dielectric coating (index η) over a diffuse base, as Mitsuba
// defines its `plastic` (smooth coating) and `roughplastic` (microfacet
// coating) BSDFs (Mitsuba 3 documentation and src/bsdfs/{plastic,roughplastic}.cpp;
// the same model as Mitsuba 0.6). With F the coating's Fresnel reflectance and
// T(μ) the fraction of light a direction at cos θ = μ sends through the coating:
//
//   f(wo, wi) = specular · f_coat(wo, wi)
//             + ρ' / π · η⁻² · T(μo) · T(μi),     ρ' = ρ / (1 − F_int)      (linear)
//                                                  ρ' = ρ / (1 − ρ·F_int)    (nonlinear)
//
// where F_int is the base's light reflected back down by the coating's
// underside, averaged over a cosine-weighted hemisphere, so ρ' sums the
// inter-reflections between base and coating (a geometric series; the linear
// form is Mitsuba's default, the nonlinear one its `nonlinear` option, which
// darkens and saturates colours as real wet or varnished surfaces do).
//
//  * Smooth coating: f_coat is a delta mirror reflection weighted by F(μo);
//    T(μ) = 1 − F(μ); F_int is Mitsuba's polynomial fit to the hemispherical
//    Fresnel average at 1/η (fresnel_diffuse_reflectance; Egan & Hilgeman
//    1973 for an argument below 1).
//  * Rough coating: f_coat = D F G / (4 μo μi) (Walter et al. 2007), Beckmann
//    or GGX with Mitsuba's separable Smith masking by default. As Mitsuba 3
//    computes them when the material is made (roughplastic.cpp, with
//    render/microfacet.h's eval_transmittance and eval_reflectance): T(μ) is
//    the share of light the rough interface refracts down, unmasked, at 64
//    values of μ, interpolated linearly; F_int is 2 · the mean over those μ of
//    R(μ; 1/η) · μ, R the interface's reflected share from inside.
//
// Sampling (Mitsuba's): the coating with probability ∝ F(μo)·w_s (rough:
// (1 − T(μo))·w_s), the base (cosine-weighted) with ∝ (1 − F(μo))·(1 − w_s),
// w_s = mean(specular) / (mean(specular) + mean(ρ)). ρ is the base's colour
// times its texture; w_s uses the texture's mean over the surface, not its
// value at the hit, so pdfs stay independent of the texture (material.h).
//
// Like lightbench's other reflecting materials, both sides of the surface are
// the coated side (Mitsuba's plastics are black from behind; the importer says so).
// f is symmetric in wo and wi, so both transport modes share it.
#include <array>
#include "core/bsdfs/material.h"
#include "core/bsdfs/microfacet.h"

namespace lb {

struct PlasticParams {
  Color diffuse{0.5f};            // ρ, the base's reflectance (times the texture)
  Color diffuseMean{0.5f};        // ρ's mean over the surface, for the lobe choice
  Color specular{1.f};            // a factor on the coating's reflection (1 is physical)
  float eta = 1.49f / 1.000277f;  // the coating's index over the outside's (polypropylene in air)
  float alpha = 0;                // 0: a smooth coating
  MicrofacetKind kind = MicrofacetKind::Beckmann;
  Masking masking = Masking::Separable;
  bool nonlinear = false;
};

// The hemispherical average of Fresnel reflectance at relative index eta,
// 2∫ F(μ) μ dμ, by the polynomial fits Mitsuba uses (d'Eon & Irving 2011 for
// eta ≥ 1; Egan & Hilgeman 1973 below).
float fresnelDiffuseReflectance(float eta);

class Plastic final : public LobeTexturedMaterial {
 public:
  static constexpr int TableSize = 64;
  explicit Plastic(const PlasticParams& params);

  BSDFEval evalTextured(const Vec3& wo, const Vec3& wi, TransportMode mode, const Color& texture) const override;
  std::optional<BSDFSample> sampleTextured(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode,
                                           const Color& texture) const override;
  float pdf(const Vec3& wo, const Vec3& wi) const override;
  uint32_t flags() const override {
    return BSDFReflection | BSDFDiffuse | (smooth() ? BSDFSpecular : BSDFGlossy);
  }

  bool smooth() const { return params_.alpha == 0; }
  // T(μ): the fraction of light at cos θ = μ that the coating lets through.
  float transmittance(float mu) const;
  // F_int: the base's light the coating sends back down.
  float internalReflectance() const { return internalReflectance_; }
  const PlasticParams& params() const { return params_; }

 private:
  float coatProbability(float muO) const;  // chance of sampling the coating, seen from wo
  Color coatF(const Vec3& wo, const Vec3& wi) const;   // rough coating, upper hemisphere
  float coatPdf(const Vec3& wo, const Vec3& wi) const;  // its sampling density, upper hemisphere
  Color baseF(float muO, float muI, const Color& texture) const;

  PlasticParams params_;
  Microfacet mf_;
  float specularWeight_;  // w_s
  float internalReflectance_;
  std::array<float, TableSize> transmittance_{};  // rough coating: T at μ = k / (TableSize − 1)
};

}  // namespace lb
