#include "integrators/bidirectional/all_strategies.h"

namespace lb::bidir {

void SubpathBuffers::fit(const PathLength& length) {
  size_t cameraCapacity = size_t(std::min(length.maxSegments(), 1 << 12)) + 1;
  camera.resize(cameraCapacity);
  light.resize(std::max<size_t>(1, cameraCapacity - 1));
}

}  // namespace lb::bidir
