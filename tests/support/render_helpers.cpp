#include "tests/support/render_helpers.h"
#include <tbb/global_control.h>
#include <sstream>
#include "integrators/registry.h"
#include "integrators/render_loop.h"

namespace lb::test {

std::string sourcePath(const std::string& relative) { return std::string(LIGHTBENCH_SOURCE_DIR) + "/" + relative; }

SceneFile loadShippedScene(const std::string& name, int width, int height, const std::string& extraYaml) {
  std::string path = sourcePath("scenes/" + name + ".yaml");
  YAML::Node root = loadYamlFile(path);
  root["film"]["width"] = width;
  root["film"]["height"] = height;
  if (!extraYaml.empty()) {
    YAML::Node extra = YAML::Load(extraYaml);
    for (auto it = extra.begin(); it != extra.end(); ++it) root[it->first.as<std::string>()] = it->second;
  }
  YAML::Emitter out;
  out << root;
  return loadSceneFromString(out.c_str(), path);
}

std::unique_ptr<Film> renderScene(const SceneFile& sf, const RenderSpec& spec) {
  std::unique_ptr<tbb::global_control> limit;
  if (spec.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(spec.threads));
  Params params(YAML::Load(spec.params), "<test>", "integrator");
  auto integrator = makeIntegrator(spec.integrator, params);
  auto film = std::make_unique<Film>(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = spec.seed;
  options.budget.spp = spec.spp;
  renderLoop(*sf.scene, *integrator, *film, sf.sampler, options);
  return film;
}

RegionMeans regionMeans(const Film& film, int rx, int ry) {
  RegionMeans r;
  r.regionsX = rx, r.regionsY = ry;
  r.mean.assign(size_t(rx * ry * 3), 0);
  r.varianceOfMean.assign(size_t(rx * ry * 3), 0);
  std::vector<double> count(size_t(rx * ry), 0);
  Image img = film.image(), var = film.varianceOfMean();
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      size_t region = size_t((y * ry / film.height()) * rx + x * rx / film.width());
      for (int c = 0; c < 3; ++c) {
        r.mean[region * 3 + c] += img.at(x, y)[c];
        r.varianceOfMean[region * 3 + c] += var.at(x, y)[c];
      }
      count[region] += 1;
    }
  for (size_t i = 0; i < r.mean.size(); ++i) {
    r.mean[i] /= count[i / 3];
    r.varianceOfMean[i] /= count[i / 3] * count[i / 3];
  }
  return r;
}

std::string compareRegions(const RegionMeans& a, const RegionMeans& b, double alpha) {
  int n = int(a.mean.size());
  double critical = normalCritical(sidak(alpha, n));
  std::ostringstream out;
  for (int i = 0; i < n; ++i) {
    double z = zScore(a.mean[i], a.varianceOfMean[i], b.mean[i], b.varianceOfMean[i]);
    if (!(std::abs(z) <= critical))
      out << "region (" << (i / 3) % a.regionsX << "," << (i / 3) / a.regionsX << ") channel " << "RGB"[i % 3] << ": " << a.mean[i] << " vs " << b.mean[i]
          << ", z = " << z << " (critical " << critical << ")\n";
  }
  return out.str();
}

}  // namespace lb::test
