#include "integrators/bidirectional/all_strategies.h"
#include "integrators/bidirectional/subpaths.h"

namespace lb::bidir {

void SubpathBuffers::fit(const PathLength& length) {
  size_t cameraCapacity = size_t(std::min(length.maxSegments(), 1 << 12)) + 1;
  camera.resize(cameraCapacity);
  light.resize(std::max<size_t>(1, cameraCapacity - 1));
}

void sampleAllStrategies(const Scene& scene, const SampleStreams& streams, const PathLength& length,
                         MisWeighting mis, Vec2 raster, SubpathBuffers& buffers, uint64_t& rays,
                         const StrategyCallback& onStrategy) {
  const int maxSeg = length.maxSegments();
  int nCamera = generateCameraSubpath(scene, streams.camera, length, raster, buffers.camera, rays);
  int nLight = generateLightSubpath(scene, streams.light, length, buffers.light, rays);
  // s = 1 samples its own light point, so it runs even when the light
  // subpath is empty (emission sampling failed).
  for (int t = 1; t <= nCamera; ++t)
    for (int s = 0; s <= std::max(nLight, 1); ++s) {
      int segments = s + t - 1;
      if ((s == 1 && t == 1) || segments < 1 || segments > maxSeg) continue;  // (1,1) is covered by (0,2) (pbrt-v3)
      Connection c = connect(scene, streams.connection, mis, buffers.light, buffers.camera, s, t, rays);
      if (isBlack(c.L) || c.weight == 0) continue;
      onStrategy(s, t, c);
    }
}

}  // namespace lb::bidir
