#pragma once
// Complex indices of refraction of a few metals as RGB (eta and k at about
// 650, 550 and 450 nm), the fits Mitsuba's and Tungsten's scenes write and
// pbrt-v4's tabulated spectra (metal-Au-eta, ...) reduce to. Shared by the
// Mitsuba and pbrt importers, so a metal is the same metal in either format.
#include <glm/glm.hpp>
#include <map>
#include <string>

namespace lb {

struct ComplexIor {
  glm::dvec3 eta, k;
};

// By chemical symbol: Au, Ag, Cu, Al. nullptr for another name.
inline const ComplexIor* namedConductor(const std::string& symbol) {
  static const std::map<std::string, ComplexIor> table = {
      {"Au", {{0.143119, 0.374957, 1.44248}, {3.98316, 2.38572, 1.60322}}},
      {"Ag", {{0.155265, 0.116723, 0.138342}, {4.82835, 3.12225, 2.14696}}},
      {"Cu", {{0.200438, 0.924033, 1.10221}, {3.91295, 2.45285, 2.14219}}},
      {"Al", {{1.65746, 0.880369, 0.521229}, {9.22387, 6.26952, 4.837}}}};
  auto it = table.find(symbol);
  return it == table.end() ? nullptr : &it->second;
}

}  // namespace lb
