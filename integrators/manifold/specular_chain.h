#pragma once
// Connecting a point to a light through smooth refracting interfaces: the
// solver of manifold next-event estimation (Hanika, Droske & Fascione 2015,
// "Manifold Next Event Estimation", on the specular manifolds of Jakob &
// Marschner 2012, "Manifold Exploration"). Used by the path tracer's
// `mnee: true` (path_estimator.h); specular manifold sampling would seed the
// same solver from other points.
//
// The chain. x_0 is a point on a non-delta surface, y a point on a light;
// x_1 … x_k (k ≤ MaxChain) lie on smooth dielectric surfaces (SmoothDielectric),
// where they refract, or on smooth mirrors (SmoothConductor), where they
// reflect: light from y reaches x_0 through them. (MNEE's straight seed
// crosses only refracting surfaces; SMS's seeds reach mirrors too.)
//
// The constraint (Hanika et al. §4.1; Jakob & Marschner Eq. 9). At x_i, with
// ω_i = (x_{i−1} − x_i)/|·|, ω_o = (x_{i+1} − x_i)/|·| and η_i, η_o the indices
// of refraction on their sides, the generalised half vector
//     h_i = (η_i ω_i + η_o ω_o) / |·|
// is parallel to the shading normal n_i exactly where Snell's law holds
// (at a mirror, η_i = η_o = 1: the law of reflection), so
//     c_i = (h_i · s_i, h_i · t_i) = 0,   (s_i, t_i) a tangent frame of n_i.
//
// Newton's method. Seeded by the straight segment x_0 → y (its crossings of
// refracting surfaces are x_1 … x_k), each step moves the vertices in their
// tangent planes by Δ = −A⁻¹ c, A = ∂c/∂(x_1 … x_k) (2k × 2k, block
// tridiagonal, c_i depending on x_{i−1}, x_i, x_{i+1}), and projects the moved
// points back onto the scene by tracing from x_0 through them (§4.2: "the new
// vertices are found by ray tracing"); a step whose rays miss or meet another
// surface is halved. The derivatives are central differences of c in double
// precision on each vertex's own surface: the triangle's plane with its
// linearly interpolated shading normal (exact on a mesh, where the paper
// differentiates the same interpolation), or the sphere.
//
// The generalised geometry term (§4.3, Eq. 7; Jakob & Marschner §4.2). With y
// fixed, the solution is a function of x_0 on its surface and, by the implicit
// function theorem, ∂(x_1 … x_k)/∂x_0 = −A⁻¹ B with B = ∂c/∂x_0. Power that
// leaves dA_y into the solid angle dω_y around ω_y = (x_k − y)/|·| lands on
// dA_0, so
//     |dω_y / dA_0| = |cos θ_k| / |x_k − y|² · |det ∂x_k/∂x_0|
// (θ_k between ω_y and x_k's geometric normal, both tangent frames
// orthonormal). Without a chain it is |cos θ_0| / |x_0 − y|². The estimate at
// x_0 of light sampled at y with area density p_A(y) is then
//     f(ω_0) |cos θ_0| · T · L_e(y, −ω_y) |cos θ_y| · |dω_y/dA_0| / (|cos θ_0| p_A(y)),
// T the product of the Fresnel transmittances (reflectances at mirrors). Radiance's 1/η² scaling is
// inside |dω_y/dA_0| (conservation of étendue, n² cos θ dA dω), not a factor of
// its own. For a point light, L_e |cos θ_y| becomes the intensity I(ω_y).
//
// Bias. The solver finds the solution its seed leads to, or none (no
// convergence, a rejected step); where a configuration has several (a curved
// or wavy surface) the others are lost. MNEE as published is biased there,
// and so is this (docs/integrator-guide.md, tests/integrators/mnee_test.cpp).
#include <optional>
#include "core/scene.h"

namespace lb {

struct ManifoldSettings {
  int maxChain = 2;          // refracting vertices a chain may have (1 or 2)
  int maxIterations = 20;    // Newton steps before giving up
  double tolerance = 1e-5;   // max |c_i| component accepted as a solution
};

struct ManifoldConnection {
  static constexpr int MaxChain = 2;
  int k = 0;                              // x_1 … x_k
  SurfaceInteraction vertices[MaxChain];  // as the scene's rays found them
  Vec3 wi{0.f};                           // unit direction from x_0 towards x_1
  double geometry = 0;                    // |dω_y/dA_0|
  Color throughput{1.f};                  // Π of 1 − F(θ_i) at glass, F(θ_i) at a mirror (Fresnel)
  int iterations = 0;                     // Newton steps taken
};

// A specular chain from `x0` (a point on a non-delta surface: p, ng) to the
// light point `y`. None if the straight segment crosses no refracting surface
// (ordinary next-event estimation covers it), crosses something else, or
// more than maxChain of them, or if Newton's method does not converge to a
// chain that refracts at every vertex. The last segment, x_k → y, is not
// tested for occlusion: the caller's shadow ray does that.
std::optional<ManifoldConnection> connectThroughSpecularChain(const Scene& scene, const SurfaceInteraction& x0,
                                                              const Vec3& y, const ManifoldSettings& settings);

// Newton's method from the chain `seeds` (x_1 … x_k, k ≤ MaxChain, points
// of smooth dielectrics as the scene's rays met them), as above: MNEE seeds
// it with the straight segment, specular manifold sampling with random
// points of the glass.
std::optional<ManifoldConnection> solveSpecularChain(const Scene& scene, const SurfaceInteraction& x0, const Vec3& y,
                                                     const SurfaceInteraction* seeds, int k,
                                                     const ManifoldSettings& settings);
// Whether a chain vertex may lie at `si` (a smooth dielectric or mirror the
// solver can differentiate: a sphere or a mesh, not instanced, no normal or
// bump map).
bool isSpecularChainSurface(const Scene& scene, const SurfaceInteraction& si);

// The chain's vertices a straight segment from x0 to y crosses (its seed):
// false if a crossing is not a usable smooth refracting surface or there are
// more than `maxChain` of them.
bool seedSpecularChain(const Scene& scene, const SurfaceInteraction& x0, const Vec3& y, int maxChain,
                       SurfaceInteraction* seeds, int* k);

}  // namespace lb
