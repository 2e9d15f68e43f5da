#pragma once
// Verification routines for the bidirectional bookkeeping (testing.md §4; the idea of
// Mitsuba 0.6's Path::verify): recompute every density from the BSDFs, lights
// and camera, and evaluate all strategies' MIS weights for a complete path.
#include <functional>
#include <vector>
#include "integrators/bidirectional/connect.h"

namespace lb::bidir {

struct PdfMismatch {
  int vertex;
  bool reverse;
  float cached, recomputed;
};

// Compares each vertex's cached pdfFwd (vertices 1…n-1) and pdfRev (0…n-3;
// n-2's is always recomputed where it is used) with a fresh recomputation.
std::vector<PdfMismatch> checkSubpathPdfs(const Scene& scene, const std::vector<Vertex>& path, int n, bool lightPath);

// A complete path from the camera (vertex 0) to a light (vertex n-1: a Light
// vertex or an emitting surface). For every split into s light and t camera
// vertices (s + t = n) it builds both subpaths with freshly computed
// densities and returns the MIS weight of (s, t), or -1 where that strategy
// cannot produce the path (a delta vertex or a delta light at its connection).
std::vector<float> strategyWeights(const Scene& scene, MisWeighting h, const std::vector<Vertex>& fullPath);

// The weights of mis.h computed by walking every vertex of both subpaths
// (O(s + t); pbrt-v3 §16.3.4 with merges), from the stored densities alone.
// Temporarily edits the connection vertices and restores them. Tests check
// the O(1) techniqueWeights against it and against the from-definition oracle.
// `factor`, if given, multiplies each connection strategy (s', t')'s density
// by factor(s', t') (variance-aware MIS, strategy_factors.h, which is why
// `bdpt` with mis: variance_aware weighs by this walk).
TechniqueWeights techniqueWeightsByWalk(const Scene& scene, MisWeighting heuristic, const Techniques& allowed,
                                        std::vector<Vertex>& light, std::vector<Vertex>& camera,
                                        const Vertex& sampled, int s, int t, const Vertex* merged = nullptr,
                                        const std::function<double(int, int)>* factor = nullptr);

}  // namespace lb::bidir
