#pragma once
// Environment maps and rotations for the environment-map tests
// (tests/core/environment_map_test.cpp, environment_map_compensation_test.cpp).
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include "core/image.h"

namespace lb::test {

// A smooth sky (so that the χ² harness's quadrature of the piecewise-constant
// pdf stays accurate) with a bright sun and a colour gradient. The sun lifts
// the map's mean above most of the sky: MIS compensation's case.
inline Image skyWithSun(int w = 64, int h = 32) {
  Image map(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double u = (x + 0.5) / w, v = (y + 0.5) / h;
      double sun = 30 * std::exp(-(std::pow(u - 0.3, 2) + std::pow(v - 0.3, 2)) / 0.01);
      map.at(x, y) = Color(float(0.2 + sun), float(0.3 + 0.5 * (1 - v) + sun), float(0.6 * (1 - v) + 0.8 * sun));
    }
  return map;
}

// A rotation by `degrees` about `axis` (a map's to_world).
inline Mat3 rotationAbout(float degrees, Vec3 axis) {
  return Mat3(glm::rotate(Mat4(1.f), glm::radians(degrees), glm::normalize(axis)));
}

}  // namespace lb::test
