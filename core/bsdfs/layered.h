#pragma once
// pbrt-v4's layered BSDFs (Pharr, Jakob and Humphreys 2023, §14.3): a
// dielectric coating (smooth or rough) over a base, diffuse (`coateddiffuse`)
// or a conductor (`coatedconductor`), a layer of `thickness` between them
// that attenuates by exp(−thickness/|cos θ|) per crossing (pbrt's medium of
// unit density and zero albedo). Light may bounce between the coating and the
// base any number of times; pbrt-v4 does not sum that in closed form but
// estimates it by random walks, and so does this material:
//  * eval()'s f is a Monte Carlo estimate: `samples` walks from both ends,
//    joined by next-event estimation with the power heuristic at each
//    interface, ended by Russian roulette or after `max_depth` bounces;
//  * pdf() is an estimate too (the TRT and TT terms of §14.3.3), mixed 9 : 1
//    with the uniform sphere's density so it is never 0 where f is not;
//  * sample() follows one walk; its weight f·|cos θ|/pdf is the walk's.
// Each estimate draws its random numbers from a hash of its directions (and
// sample()'s of its own random numbers), as pbrt-v4 does: eval() and pdf()
// are fixed functions of (wo, wi), so the MIS weights integrators compute from
// them at different times agree, and images stay bit-identical across
// threads. Every integrator therefore accepts this material: sample() reports
// pdf() as its pdf (with f scaled to keep the walk's weight), which is what
// pbrt-v4's "pdfIsProportional" samples give its MIS.
//
// Differences from pbrt-v4: no medium albedo or phase function between the
// layers (pbrt's defaults, albedo 0, are what is modelled), RGB not sampled
// wavelengths, lightbench's own hash and generator, pdf() 0 below the
// surface (the bases are opaque), and one MIS weight in f that pbrt-v4 takes
// with its density reversed (layered.cpp says which): with pbrt's weight,
// f integrates to 7 % more than the walks sample() follows deliver.
#include <memory>
#include "core/bsdfs/material.h"
#include "core/bsdfs/microfacet.h"

namespace lb {

struct LayeredParams {
  float eta = 1.5f;       // the coating's index over the outside's
  float alpha = 0;        // the coating's microfacet alpha (0: smooth)
  MicrofacetKind kind = MicrofacetKind::GGX;
  float thickness = 0.01f;
  int maxDepth = 10;
  int samples = 1;
};

class Layered final : public LobeTexturedMaterial {
 public:
  // `base` reflects only (a Diffuse or a conductor); a texture scales its f.
  Layered(const LayeredParams& params, std::unique_ptr<Material> base);
  ~Layered() override;

  BSDFEval evalTextured(const Vec3& wo, const Vec3& wi, TransportMode mode, const Color& texture) const override;
  std::optional<BSDFSample> sampleTextured(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode,
                                           const Color& texture) const override;
  float pdf(const Vec3& wo, const Vec3& wi) const override;
  uint32_t flags() const override;
  bool exactDensity() const override { return false; }  // pdf() is an estimate

  // The estimate of f alone (eval() adds both pdfs): the tests average it.
  Color f(Vec3 wo, Vec3 wi, TransportMode mode, const Color& texture) const;

 private:
  class Interface;
  LayeredParams p_;
  std::unique_ptr<Material> coating_, base_;
};

}  // namespace lb
