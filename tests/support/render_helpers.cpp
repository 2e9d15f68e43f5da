#include "tests/support/render_helpers.h"
#include "core/scene_import.h"
#include <tbb/global_control.h>
#include <sstream>
#include "integrators/registry.h"
#include "integrators/render_loop.h"

namespace lb::test {

std::string sourcePath(const std::string& relative) { return std::string(LIGHTBENCH_SOURCE_DIR) + "/" + relative; }

SceneFile loadShippedScene(const std::string& name, int width, int height, const std::string& extraYaml) {
  if (isImportedScenePath(name)) {
    // An imported scene (scenes/external/…): resized and varied through the
    // loader's overrides, as an experiment does.
    YAML::Node overrides = YAML::Load(extraYaml);
    if (!overrides.IsMap()) overrides = YAML::Node(YAML::NodeType::Map);
    overrides["film"]["width"] = width;
    overrides["film"]["height"] = height;
    SceneLoadOptions quiet;
    quiet.quiet = true;
    return loadScene(sourcePath("scenes/" + name), overrides, quiet);
  }
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

Rendered renderWithReport(const SceneFile& sf, const RenderSpec& spec) {
  std::unique_ptr<tbb::global_control> limit;
  if (spec.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(spec.threads));
  Params params(YAML::Load(spec.params), "<test>", "integrator");
  auto integrator = makeIntegrator(spec.integrator, params);
  Rendered r;
  r.film = std::make_unique<Film>(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = spec.seed;
  options.budget.spp = spec.spp;
  options.adaptive = spec.adaptive;
  r.report = renderLoop(*sf.scene, *integrator, *r.film, sf.sampler, options);
  return r;
}

RegionMeans regionMeans(const Film& film, int rx, int ry, const std::vector<bool>* mask) {
  RegionMeans r;
  r.regionsX = rx, r.regionsY = ry;
  r.mean.assign(size_t(rx * ry * 3), 0);
  r.varianceOfMean.assign(size_t(rx * ry * 3), 0);
  std::vector<double> count(size_t(rx * ry), 0);
  Image img = film.image(), var = film.varianceOfMean();
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      if (mask && !(*mask)[size_t(y) * film.width() + x]) continue;
      size_t region = size_t((y * ry / film.height()) * rx + x * rx / film.width());
      for (int c = 0; c < 3; ++c) {
        r.mean[region * 3 + c] += img.at(x, y)[c];
        r.varianceOfMean[region * 3 + c] += var.at(x, y)[c];
      }
      count[region] += 1;
    }
  for (size_t i = 0; i < r.mean.size(); ++i) {
    if (count[i / 3] == 0) continue;  // a fully masked region compares 0 with 0
    r.mean[i] /= count[i / 3];
    r.varianceOfMean[i] /= count[i / 3] * count[i / 3];
  }
  return r;
}

std::vector<bool> primaryHitMask(const Scene& scene, const std::function<bool(bool, const SurfaceInteraction&)>& keep) {
  const Camera& cam = scene.camera;
  std::vector<bool> mask(size_t(cam.width()) * cam.height());
  const Vec2 offsets[5] = {{0.5f, 0.5f}, {0.001f, 0.001f}, {0.999f, 0.001f}, {0.001f, 0.999f}, {0.999f, 0.999f}};
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x) {
      bool ok = true;
      for (Vec2 o : offsets) {
        SurfaceInteraction si;
        bool hit = scene.intersect(cam.generateRay(Vec2(x, y) + o), si);
        ok = ok && keep(hit, si);
      }
      mask[size_t(y) * cam.width() + x] = ok;
    }
  return mask;
}

std::vector<bool> diffusePrimaryHits(const Scene& scene) {
  return primaryHitMask(scene, [](bool hit, const SurfaceInteraction& si) {
    return hit && si.material && si.material->flags() == (BSDFReflection | BSDFDiffuse);
  });
}

::testing::AssertionResult meanMatches(const Film& film, double expected, double alpha, int channel, int x0, int y0,
                                       int x1, int y1) {
  if (x1 < 0) x1 = film.width(), y1 = film.height();
  Image img = film.image(), var = film.varianceOfMean();
  double sum = 0, varSum = 0, n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) sum += img.at(x, y)[channel], varSum += var.at(x, y)[channel], n += 1;
  double mean = sum / n, varMean = varSum / (n * n);
  // Besides Monte Carlo error, each sample carries float rounding: a path's
  // few dozen single-precision operations give a relative bias of at most
  // about 32 ulp, which matters only when the estimator has (near) zero
  // variance, as in the white furnace.
  double rounding = 32 * double(MachineEpsilon) * std::abs(expected);
  double critical = normalCritical(alpha);
  double z = (std::abs(mean - expected) - rounding) / std::sqrt(varMean);
  if (std::abs(mean - expected) <= rounding || std::abs(z) <= critical) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "mean " << mean << " vs exact " << expected << ", z = " << z
                                       << " (critical " << critical << ", sd of mean " << std::sqrt(varMean) << ")";
}

const char* const PointLightPlaneScene =
    "camera: {position: [0, 3, 0], look_at: [0, 0, 0], up: [0, 0, -1], fov: 40}\n"
    "film: {width: 16, height: 16}\n"
    "materials: {m: {type: diffuse, albedo: 0.5}}\n"
    "shapes: [{type: rectangle, material: m, transform: {scale: 10, rotate_x: -90}}]\n"
    "lights: [{type: point, position: [0.3, 2, 0.2], intensity: 10}]\n";

double pointLightOverPlane(const Camera& cam, Vec3 light, float I, float rho) {
  double exact = 0;
  const int q = 8;  // 8×8 midpoint rule per pixel: error far below the MC error of these tests
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x)
      for (int j = 0; j < q; ++j)
        for (int i = 0; i < q; ++i) {
          Ray r = cam.generateRay(Vec2(x + (i + 0.5f) / q, y + (j + 0.5f) / q));
          float t = -r.o.y / r.d.y;
          Vec3 p = r.o + t * r.d, toLight = light - p;
          float r2 = glm::dot(toLight, toLight), cos = toLight.y / std::sqrt(r2);
          exact += rho * I * cos / (Pi * r2);
        }
  return exact / (double(cam.width()) * cam.height() * q * q);
}

std::string compareScenes(const SceneFile& a, const SceneFile& b, RenderSpec spec, double alpha) {
  auto filmA = renderScene(a, spec);
  spec.seed += 1;
  auto filmB = renderScene(b, spec);
  return compareRegions(regionMeans(*filmA, 4, 4), regionMeans(*filmB, 4, 4), alpha);
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

std::vector<bool> causticPixels(const SceneFile& scene, const RenderSpec& selection, const std::vector<bool>& candidates) {
  Image sel = renderScene(scene, selection)->image();
  std::vector<float> values;
  for (size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i]) values.push_back(luminance(sel.pixels[i]));
  std::vector<bool> caustic(candidates.size(), false);
  if (values.empty()) return caustic;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  float median = values[values.size() / 2];
  for (size_t i = 0; i < candidates.size(); ++i) caustic[i] = candidates[i] && luminance(sel.pixels[i]) > 3 * median;
  return caustic;
}

std::string furnaceScene(float albedo) {
  return "camera: {position: [0.1, 0.2, 0.3], look_at: [1, 0, 0], fov: 60}\n"
         "film: {width: 16, height: 16}\n"
         "materials: {wall: {type: diffuse, albedo: " + std::to_string(albedo) + "}}\n"
         "shapes: [{type: sphere, radius: 2, flip_normals: true, material: wall, emission: 1}]\n";
}

}  // namespace lb::test
