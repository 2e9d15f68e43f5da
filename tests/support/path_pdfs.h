#pragma once
// Every bidirectional strategy's density for one complete path, computed
// straight from the definition, independently of BDPT's ratio recursion
// (testing.md §4: Σw = 1 is necessary, not sufficient).
//
// Veach 1997 §10.2: strategy (s, t) samples the light subpath y0…y(s-1) and
// the camera subpath z0…z(t-1) and joins them; its density is the product of
// the densities with which each sampled vertex was generated from its
// predecessor, in area measure (solid angle for a vertex at infinity):
//   p_{s,t} = p(y0) · Π_{i=1}^{s-1} p(y_i | y_{i-1}, y_{i-2}) · Π_{j=1}^{t-1} p(z_j | z_{j-1}, z_{j-2}),
// with p(x_j | x_{j-1}, …) = p_σ(x_{j-1} → x_j) · |cos θ_j| / d² (no 1/d², and
// no cosine, at infinity). At a specular vertex the directional density is a
// delta; Veach's §8.2.2 factors it out of every strategy alike, so here it
// counts as 1 (the lobe-selection probability is symmetric and cancels too),
// measured in the direction the camera side samples it: a refraction sampled
// from the light side carries the other side's delta, which differs by the
// refraction map's Jacobian η² cos θ ratio (étendue; lightSideDelta in the .cpp).
// The light endpoint y0 is sampled by emission (pdfLe: position, then
// direction) for s ≥ 2 and by next-event estimation (pdfLi) for s = 1; delta
// positions and directions of point, spot and directional lights count as 1,
// leaving the light-selection probability.
//
// Strategies: s = 0 needs an emitter that rays can hit; (s, t) = (1, 1) is
// not used (s = 0, t = 2 covers it, as in pbrt); any other strategy needs
// both connection vertices to be non-specular (y0 always connects, by NEE).
// Everything is evaluated in double from the vertices' positions, normals and
// materials, calling only the BSDFs', lights' and camera's own pdfs.
#include <vector>
#include "integrators/bidirectional/connect.h"

namespace lb::test {

// path[0] is the camera, path.back() the light end (an emitting surface, a
// light vertex, or an escaped camera ray). Returns p_{s, n-s} for s = 0…n-1,
// 0 where strategy s cannot generate the path.
std::vector<double> strategyPdfsFromDefinition(const Scene& scene, const std::vector<bidir::Vertex>& path);

// Vertex merging (Georgiev, Křivánek, Davidovič, Slusallek 2012, §4): the
// camera subpath path[0…k] and the light subpath y0…path[k], both sampled,
// joined at path[k] with acceptance π r²:
//   m_k = Π_{j=1}^{k} p(z_j | …) · p_emit(y0) · Π_{i=1}^{n-1-k} p(y_i | …) · η,
// η = N π r² (N light subpaths per iteration). Needs a non-specular surface
// at path[k] that is neither end (1 ≤ k ≤ n-2). Returns m_k for k = 0…n-1,
// 0 where merging at k cannot generate the path.
std::vector<double> mergePdfsFromDefinition(const Scene& scene, const std::vector<bidir::Vertex>& path, double eta);

// The heuristic applied to those densities: w_s = p_s^β / Σ_i p_i^β (β = 1
// balance, 2 power); uniform: 1 / (number of strategies with p_i > 0).
std::vector<double> weightsFromPdfs(const std::vector<double>& pdfs, bidir::MisWeighting h);

}  // namespace lb::test
