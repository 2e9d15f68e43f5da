#pragma once
// Builds a material from its YAML description; rejects non-physical values.
#include <memory>
#include "core/bsdfs/material.h"
#include "core/params.h"

namespace lb {

// Types: diffuse {albedo, texture}, conductor {roughness, distribution, tint,
// eta, k, texture}, dielectric {ior, roughness, distribution}, thin_dielectric
// {ior}. roughness is the microfacet alpha of `distribution` (ggx, the
// default, or beckmann); below 1e-3 the smooth (delta) model is used. A texture's
// files are relative to `folder` (the scene's).
std::unique_ptr<Material> makeMaterial(Params& params, const std::string& folder = ".");

}  // namespace lb
