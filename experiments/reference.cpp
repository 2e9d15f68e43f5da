#include "experiments/reference.h"
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include "core/scene_loader.h"
#include "integrators/registry.h"

namespace lb {

namespace {
struct Fnv1a {
  uint64_t h = 0xcbf29ce484222325ULL;
  void add(const std::string& bytes) {
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ULL;
    h = (h ^ 0xff) * 0x100000001b3ULL;  // separator, so "ab"+"c" differs from "a"+"bc"
  }
  std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", (unsigned long long)h);
    return out;
  }
};
std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

std::string hashStrings(const std::vector<std::string>& parts) {
  Fnv1a f;
  for (const auto& p : parts) f.add(p);
  return f.hex();
}

namespace {
// The scene a reference is rendered from, and its overrides.
const std::string& referenceScene(const ExperimentScene& s) { return s.reference.scene.empty() ? s.path : s.reference.scene; }
const YAML::Node& referenceOverrides(const ExperimentScene& s) {
  return s.reference.scene.empty() ? s.overrides : s.resolution;
}
// Cached references are named after the scene they are rendered from, so
// runs sharing one (a scale sweep against the unscaled scene) share the file.
std::string referenceName(const ExperimentScene& s) {
  return s.reference.scene.empty() ? s.name : std::filesystem::path(s.reference.scene).stem().string();
}
}  // namespace

std::string referenceKey(const ExperimentScene& s) {
  Fnv1a f;
  // The renderer's version and commit: a fixed integrator must not keep
  // serving references computed before the fix.
  f.add("lightbench-reference-v1 " LIGHTBENCH_VERSION " " LIGHTBENCH_GIT);
  const std::string& scene = referenceScene(s);
  f.add(readBytes(scene));
  YAML::Node root = loadYamlFile(scene);
  std::string folder = std::filesystem::path(scene).parent_path().string();
  if (root["shapes"] && root["shapes"].IsSequence())
    for (const auto& shape : root["shapes"])
      if (shape.IsMap() && shape["file"]) f.add(readBytes((std::filesystem::path(folder) / shape["file"].as<std::string>()).string()));
  f.add(flowYaml(referenceOverrides(s)));
  f.add(s.reference.integrator);
  f.add(flowYaml(s.reference.params));
  f.add(std::to_string(s.reference.spp) + "/" + std::to_string(s.reference.seed));
  return f.hex();
}

Reference obtainReference(const ExperimentScene& s, const std::string& resultsRoot, const std::string& key) {
  if (!s.reference.file.empty()) {
    std::cerr << "reference: " << s.reference.file << " (given)\n";
    return {readExr(s.reference.file)};
  }
  std::filesystem::path dir = std::filesystem::path(resultsRoot) / "references";
  std::filesystem::create_directories(dir);
  std::filesystem::path exr = dir / (referenceName(s) + "-" + key + ".exr");
  std::filesystem::path sidecar = dir / (referenceName(s) + "-" + key + ".yaml");
  if (std::filesystem::exists(exr)) {
    std::cerr << "reference: " << exr.string() << " (cached)\n";
    Reference r{readExr(exr.string())};
    if (std::filesystem::exists(sidecar)) {
      // The sidecar is ours, but a user may have edited or truncated it.
      Params info(loadYamlFile(sidecar.string()), sidecar.string(), "");
      if (info.has("variance_of_mean")) r.varianceOfMean = info.getFloat("variance_of_mean", 0);
    }
    return r;
  }
 std::cerr << "reference: rendering " << referenceName(s) << " with '" << s.reference.integrator << "' at "
            << s.reference.spp << " spp (cached for later runs as " << exr.string() << ")\n";
  SceneFile sf = loadScene(referenceScene(s), referenceOverrides(s));
  Params params(s.reference.params, s.path, "reference.params");
  auto integrator = makeIntegrator(s.reference.integrator, params);
  Film film(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = s.reference.seed;
  options.budget.spp = s.reference.spp;
  options.progress = true;
  RenderReport rep = renderLoop(*sf.scene, *integrator, film, sf.sampler, options);
  Image image = film.image();
  writeExr(exr.string(), image);
  std::ostringstream info;
  info << "scene: " << referenceScene(s) << "\nintegrator: " << s.reference.integrator << "\nparams: " << flowYaml(s.reference.params)
       << "\nspp: " << s.reference.spp << "\nseed: " << s.reference.seed << "\nseconds: " << rep.seconds
       << "\nnon_finite_samples: " << rep.nonFinite << "\nvariance_of_mean: " << film.meanVarianceOfMean()
       << "\nkey: " << key << "\n";
  writeTextFile(sidecar.string(), info.str());
  return {image, film.meanVarianceOfMean()};
}

}  // namespace lb
