#pragma once
// Builds a material from its YAML description; rejects non-physical values.
#include <memory>
#include "core/bsdfs/material.h"
#include "core/params.h"

namespace lb {

// Types: diffuse {albedo}, conductor {roughness, tint, eta, k},
// dielectric {ior, roughness}. roughness is the GGX alpha; below 1e-3 the
// smooth (delta) model is used.
std::unique_ptr<Material> makeMaterial(Params& params);

}  // namespace lb
