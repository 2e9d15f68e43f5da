#pragma once
// What a material's surface maps (Material::SurfaceMaps) do at a hit.
//
// Normal and bump maps replace the shading normal; the geometric normal, and
// so the ray offsets and the light-leak test of core/bsdfs/bsdf.h, stay the
// surface's own. The new frame is built from the new normal alone, as every
// other shading frame is (Frame(n)): lightbench's BSDFs are isotropic, so the
// tangents' rotation about n changes nothing, and a flat bump map leaves the
// frame as it was.
//
// Opacity is a property of the surface, not of its BSDF: where it is α < 1, a
// ray passes the surface with probability 1 − α (Embree's intersection
// filter, core/scene.cpp), for camera, shadow and light rays alike. That is
// Mitsuba's `mask` (its nested BSDF with weight α, a straight pass-through
// with 1 − α) and pbrt-v4's `alpha`, sampled rather than weighted, so every
// estimator sees one surface that is there or not. The choice is a hash of
// the ray and the primitive, as in pbrt-v4 (Pharr et al. 2023, §7.1.1), so a
// ray retraced (a shadow ray along a path segment) decides alike and no
// sampler dimension is spent; hashing the primitive too keeps two masked
// layers on one ray independent.
#include "core/bsdfs/material.h"
#include "core/interaction.h"

namespace lb {

// The opacity a texture's value means: its luminance, clamped to [0, 1]
// (Mitsuba's mask takes the luminance of its opacity spectrum).
float opacityOf(const Color& value);

// Replaces si.shading by the material's normal or bump map. si.dpdu and
// si.dpdv must be set (Shape::surfaceTangents).
//  * Normal map (Mitsuba 3 `normalmap`, pbrt-v4 `normalmap`): the texel's
//    linear RGB c gives n = 2c − 1 in the frame (s, n × s, n), s the shading
//    normal's tangent along ∂p/∂u.
//  * Bump map (Mitsuba 0.6 `bumpmap`, pbrt-v4 `displacement`): a displacement
//    d(u, v) = scale · luminance moves the surface along n; the displaced
//    tangents are ∂p/∂u projected on the tangent plane plus n ∂d/∂u (likewise
//    v; Mitsuba 0.6's bumpmap.cpp, pbrt-v4 BumpMap without its dn/du term),
//    and the new normal is their cross product, turned to the side of the
//    old one (Blinn 1978).
void applyShadingMaps(const Material& material, SurfaceInteraction& si);

// Whether a ray (o, d) passes a surface of opacity alpha on primitive
// (geometry, primitive): always for alpha <= 0, never for alpha >= 1, else
// with probability 1 − alpha over rays.
bool passesThrough(float alpha, const Vec3& o, const Vec3& d, unsigned geometry, unsigned primitive);

}  // namespace lb
