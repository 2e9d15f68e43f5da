#pragma once
// Shared set-up for integrator tests: load a shipped scene at a small size (or a
// scene from text), render it with an integrator, and compare region means.
#include <memory>
#include <string>
#include "core/film.h"
#include "core/scene_loader.h"
#include "tests/support/statistics.h"

namespace lb::test {

std::string sourcePath(const std::string& relative);
// A shipped scene (scenes/NAME.yaml) with its film resized; extra top-level
// YAML (e.g. "world_scale: 100") may be merged in.
SceneFile loadShippedScene(const std::string& name, int width, int height, const std::string& extraYaml = "");

struct RenderSpec {
  std::string integrator = "path";
  std::string params = "{}";  // YAML mapping of integrator parameters
  uint64_t spp = 16;
  uint64_t seed = 1;
  int threads = 0;            // 0: default
};
std::unique_ptr<Film> renderScene(const SceneFile& scene, const RenderSpec& spec);

// Means over a grid of rectangular regions, with the variance of each mean
// taken from the film's per-pixel variance estimates (independent pixels).
struct RegionMeans {
  int regionsX = 0, regionsY = 0;
  std::vector<double> mean, varianceOfMean;  // per region and channel: [region * 3 + c]
};
RegionMeans regionMeans(const Film& film, int regionsX, int regionsY);

// z-tests of A against B over all regions, Šidák-corrected at level alpha;
// returns a description of every failing region (empty when all pass).
std::string compareRegions(const RegionMeans& a, const RegionMeans& b, double alpha);

}  // namespace lb::test
