#pragma once
// Camera and light subpaths of the bidirectional estimators (BDPT, and those
// built on its vertices): random walks with Russian roulette whose vertices
// carry both densities (vertex.h). pbrt-v3 §16.3.2.
#include <vector>
#include "core/bsdfs/regularization.h"
#include "core/sampler.h"
#include "integrators/bidirectional/vertex.h"
#include "integrators/path_length.h"

namespace lb::bidir {

// Fixed sampler dimensions for a walk, so that a low-discrepancy sampler
// stratifies each vertex's decisions whatever the length of the other
// subpath (drawn in one stream, a light subpath's dimensions would otherwise
// start wherever the camera subpath stopped): the scattering at vertex k ≥ 1
// (its lobe, direction and roulette: 4 dimensions) starts at dimension
// first + stride · (k − 1), and a light subpath's emission (6) at `emission`.
// stride 0 draws sequentially from wherever the sampler is (MLT's streams).
struct WalkDimensions {
  uint32_t first = 0, stride = 0, emission = 0;
};

// Where a camera walk ends: at the length's bound (and roulette), or also at
// its first vertex photons can be merged at (Vertex::mergeable: progressive
// photon mapping merges there and nowhere after, so tracing further would be
// wasted rays).
enum class WalkStop { AtLength, AtFirstNonSpecular };

// Random walks from the camera through `raster` and from a light chosen by
// the scene's light sampler. They fill `path` from index 0 and return the
// number of vertices; `path.size()` caps the walk (it must hold at least
// one vertex), `length` bounds it in segments and sets the roulette. With
// `regularization`, delta vertices scatter by this pass's rough twins where
// core/bsdfs/regularization.h says (Vertex::regularized).
int generateCameraSubpath(const Scene& scene, Sampler& sampler, const PathLength& length, Vec2 raster,
                          std::vector<Vertex>& path, uint64_t& rays, const WalkDimensions& dimensions = {},
                          WalkStop stop = WalkStop::AtLength, const Regularization* regularization = nullptr);
int generateLightSubpath(const Scene& scene, Sampler& sampler, const PathLength& length, std::vector<Vertex>& path,
                         uint64_t& rays, const WalkDimensions& dimensions = {},
                         const Regularization* regularization = nullptr);

}  // namespace lb::bidir
