#pragma once
// Multiple importance sampling over every bidirectional technique, at O(1)
// per connection or merge: partial sums carried along each subpath (the idea
// of Georgiev's "Implementing Vertex Connection and Merging", 2012, whose
// dVCM/dVC/dVM are running sums of the same kind, and of van Antwerpen's
// recursive MIS, 2011), in the densities of vertex.h.
//
// The weight of technique (s, t) is (Veach 1997, Eq. 10.9, §10.3.5)
//   w = h(p_base) / Σ_i h(p_i),   h(x) = x (balance), x² (power), [x > 0] (uniform),
// and dividing by p_base every term is a product of ratios (pbrt-v3 Eq. 16.14):
// moving the connection one vertex from x_k to its neighbour multiplies the
// density by ρ_k = pdfRev(x_k) / pdfFwd(x_k). On a subpath x_0, x_1, … (the
// camera's z or the light's y) let
//   (1)  ρ_k = pdfRev_k / pdfFwd_k,
//   (2)  a_k = [x_k and x_{k-1} not delta] · c_k · [connections allowed]
//              + [x_k mergeable] · h(pdfFwd_k · η)              (η = N π r², Georgiev et al. 2012 §4)
//        with c_k = h(n) for a connection of n expected draws per sample
//        (Techniques::connectionCount; 1 in BDPT), except c_1 = 1 on the
//        camera subpath (light tracing, t = 1), c_1 = h(p_NEE(y_0) / p_emit(y_0))
//        on the light subpath (strategy s = 1 samples y_0 by next-event
//        estimation, the base by emission), and a_0 = [y_0 and its light not
//        delta] (strategy s = 0, always a competitor);
//   (3)  S_k = h(ρ_k) · (a_k + S_{k-1}),   S_{-1} = 0 (light), S_0 = 0 (camera).
// h is multiplicative on non-negative values, so S_k is Σ_{i ≤ k} h(Π_{j=i..k} ρ_j · a_i):
// the sum over every technique whose connection (or merge) lies at or before
// x_k, relative to one whose connection lies just beyond x_k. The recursion
// is carried after a subpath is sampled (computePartialSums, O(n) once).
//
// A connection (s, t) changes the reverse densities of the two vertices on
// each side of it (they are now reached from the other subpath), so only
// those are evaluated at the connection; the rest is the stored S:
//   (4)  camera side  C = h(ρ'_{t-1}) · (a'_{t-1} + h(ρ'_{t-2}) · (a_{t-2} + S^z_{t-3}))
//   (5)  light side   L = h(ρ'_{s-1}) · (a'_{s-1} + h(ρ'_{s-2}) · (a_{s-2} + S^y_{s-3}))
//   (6)  w_(s,t) = h(own) / (h(own) + C + L),
// primes marking what the connection changes (the connection vertices are not
// delta for this path; s = 0 uses the hit emitter as y_0; s = 1 and t = 1 use
// the freshly sampled endpoint). A merge of light[0..s-1] at camera[t-1]
// (Georgiev et al. §4) keeps light[s-2]'s reverse density as cached, so its
// light side is h(ρ'_{s-1}) · (a'_{s-1} + S^y_{s-2}), and its own term is
// the merge term of a'_{t-1} times h(ρ'_{t-1}).
//
// The O(s+t) walk these sums replace (pbrt-v3 §16.3.4 extended with merges)
// is kept as techniqueWeightsByWalk (verification.h) for tests.
#include <vector>
#include "integrators/bidirectional/vertex.h"

namespace lb::bidir {

enum class MisWeighting { Balance, Power, Uniform };

// The techniques that compete for a path in the MIS weights. BDPT: every
// connection. Vertex connection and merging (Georgiev et al. 2012): merging
// at each interior non-delta vertex too, and/or no connections.
struct Techniques {
  bool connections = true;  // every (s, t) with s >= 1 (s = 0, a camera subpath hitting a light, always competes)
  float mergeEta = 0;       // > 0: merging competes, η = (light subpaths per iteration) · π r²
  // How many times, in expectation, one camera sample makes each connection
  // (s, t) with s >= 2 and t >= 2: 1 in BDPT (its own light subpath); in the
  // light-vertex-cache BDPT (Davidovič et al. 2014) k draws from a cache of M
  // vertices of N light subpaths, k·N/M. Its density enters the heuristic as
  // count × density (Veach 1997 Eq. 9.13): h(c·p) = h(c)·h(p) multiplies the
  // term of every such technique in Eqs. 2, 4, 5 and 6 below by h(c). Next-
  // event estimation (s = 1), light tracing (t = 1) and s = 0 keep count 1.
  double connectionCount = 1;
};
struct TechniqueWeights {
  float connection = 0;     // weight of the connection (s, t) itself
  float mergeAtCamera = 0;  // weight of merging light[0..s-1], extended to camera[t-1], at camera[t-1]
};

enum class SubpathSide { Camera, Light };

// Fills misSum (S_k of Eq. 3) and misBaseZero of path[0..n-1] (and, on a
// light subpath, path[0].neeOverEmit) for these techniques and heuristic.
// Call it once a subpath is sampled, and again after editing its densities;
// the weights below read what it stored.
void computePartialSums(const Scene& scene, MisWeighting h, const Techniques& allowed, std::vector<Vertex>& path,
                        int n, SubpathSide side);

// p_NEE(y0) / p_emit(y0), the light endpoint y0 seen from y1 (0 when emission cannot sample it).
float neeOverEmit(const Scene& scene, const Vertex& y0, const Vertex& y1);

// MIS weights of strategy (s, t) and of the merge at camera[t-1], Eqs. 4–6;
// `sampled` stands for y(s-1) when s = 1 and for z(t-1) when t = 1. Both
// subpaths must carry partial sums for the same heuristic and techniques.
//
// For a merge, `merged` is the light vertex found near camera[t-1], and
// light[0..s-1] its light subpath before it (so light[s-1] may be specular):
// the light subpath's density of camera[t-1] is taken as merged->pdfFwd and
// light[s-2]'s reverse density as cached, since light[s-1] may be a delta
// vertex whose densities cannot be evaluated towards another point
// (Georgiev's report stores the same quantities at the light vertex).
TechniqueWeights techniqueWeights(const Scene& scene, MisWeighting heuristic, const Techniques& allowed,
                                  Subpath light, Subpath camera,
                                  const Vertex& sampled, int s, int t, const Vertex* merged = nullptr);

// The reverse densities a connection changes (the primes of Eqs. 4–5), in
// area measure: z_{t-1} and z_{t-2} reached from the light side, y_{s-1} and
// y_{s-2} from the camera side. connect() has them from the two BSDF
// evaluations it makes anyway; this evaluates them from the vertices.
struct ConnectionDensities {
  float pt = 0, ptMinus = 0, qs = 0, qsMinus = 0;
};
ConnectionDensities connectionDensities(const Scene& scene, Subpath light,
                                        Subpath camera, const Vertex& sampled, int s, int t,
                                        const Vertex* merged = nullptr);
TechniqueWeights techniqueWeights(const Scene& scene, MisWeighting heuristic, const Techniques& allowed,
                                  Subpath light, Subpath camera,
                                  const Vertex& sampled, int s, int t, const ConnectionDensities& reverse,
                                  const Vertex* merged = nullptr);

}  // namespace lb::bidir
