#pragma once
// Camera and light subpaths of the bidirectional estimators (BDPT, and those
// built on its vertices): random walks with Russian roulette whose vertices
// carry both densities (vertex.h). pbrt-v3 §16.3.2.
#include <vector>
#include "core/sampler.h"
#include "integrators/bidirectional/vertex.h"
#include "integrators/path_length.h"

namespace lb::bidir {

// Random walks from the camera through `raster` and from a light chosen by
// the scene's light sampler. They fill `path` from index 0 and return the
// number of vertices; `path.size()` caps the walk (it must hold at least
// one vertex), `length` bounds it in segments and sets the roulette.
int generateCameraSubpath(const Scene& scene, Sampler& sampler, const PathLength& length, Vec2 raster,
                          std::vector<Vertex>& path, uint64_t& rays);
int generateLightSubpath(const Scene& scene, Sampler& sampler, const PathLength& length, std::vector<Vertex>& path,
                         uint64_t& rays);

}  // namespace lb::bidir
