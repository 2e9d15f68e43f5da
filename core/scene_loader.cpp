// The YAML scene reader (scene_loader.h): the file, its overrides, the film
// and the camera here; shapes and lights in scene_file_shapes.cpp and
// scene_file_lights.cpp, which share scene_file_parts.h. Imported Mitsuba
// and pbrt-v4 files go through core/mitsuba/ and core/pbrt/ to the same description.
#include "core/scene_loader.h"
#include "core/scene_file_parts.h"
#include "core/memory.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include "core/bsdfs/material_factory.h"
#include "core/image.h"
#include "core/scene_import.h"

namespace lb {

SamplerSettings readSamplerSettings(Params& p) {
  SamplerSettings s;
  s.type = p.getChoice("type", "independent", std::vector<std::string>(std::begin(SamplerTypes), std::end(SamplerTypes)),
                       "the random or low-discrepancy numbers each sample draws (core/sampler.h)");
  s.strata = p.getInt("strata", 4, {"stratified: strata per axis (blocks of strata² samples)", Range::between(1, 64)});
  s.spp = p.getInt("spp", 64, {"zsobol: samples per pixel of one Morton-ordered pattern", Range::between(1, 1 << 16)});
  if (s.spp & (s.spp - 1)) p.fail("spp", "must be a power of 2");
  p.checkUnused();
  return s;
}

namespace scene_file {

void checkCoordinates(Params& p, const std::string& key, const Vec3& point) {
  if (!(std::max({std::abs(point.x), std::abs(point.y), std::abs(point.z)}) <= kMaxCoordinate))
    p.fail(key, "lies beyond ±1e17 (after transforms and world_scale): rays start there, and Embree traces none "
                "from beyond ±1.8e18");
}

}  // namespace scene_file

namespace {

using namespace scene_file;

void checkFilmMemory(Params& film, int width, int height) {
  std::string problem = filmMemoryProblem(width, height);
  if (!problem.empty()) film.fail(width >= height ? "width" : "height", problem + "; lower film.width/height");
}

// The vertical field of view of one given along `axis` (Mitsuba's fov_axis:
// x, y, diagonal, or the smaller or larger image side), in degrees.
float verticalFov(float fov, const std::string& axis, int width, int height) {
  const double aspect = double(width) / height, t = std::tan(glm::radians(double(fov)) / 2);
  std::string a = axis;
  if (a == "smaller") a = aspect > 1 ? "y" : "x";
  if (a == "larger") a = aspect > 1 ? "x" : "y";
  double tanY = a == "y" ? t : a == "x" ? t / aspect : t / std::sqrt(1 + aspect * aspect);
  return float(glm::degrees(2 * std::atan(tanY)));
}

// film: {filter: {type: gaussian, sigma: 0.5}}: the pixel reconstruction
// filter (core/filter.h). Defaults as Mitsuba 3's: box ½, tent 1, gaussian
// σ ½ with radius 4σ, mitchell B = C = ⅓ with radius 2, lanczos 3 lobes.
PixelFilter readFilter(Params& f) {
  using Type = PixelFilter::Type;
  std::string name = f.getChoice("type", "box", PixelFilter::names());
  Type type = PixelFilter::typeNamed(name);
  float a = 0, b = 0, fallback = 0.5f;
  if (type == Type::Tent) fallback = 1;
  if (type == Type::Gaussian) {
    a = f.getFloat("sigma", 0.5f, {"standard deviation in pixels", Range::openClosed(0, 4)});
    fallback = 4 * a;
  }
  if (type == Type::Mitchell) {
    a = f.getFloat("b", 1.f / 3, {"Mitchell-Netravali B", Range::between(-4, 4)});
    b = f.getFloat("c", 1.f / 3, {"Mitchell-Netravali C", Range::between(-4, 4)});
    fallback = 2;
  }
  if (type == Type::Lanczos) {
    a = f.getFloat("tau", 3, {"the window's lobes (sinc(x/τ))", Range::openClosed(0, 16)});
    fallback = a;
  }
  float radius = f.getFloat("radius", fallback, {"in pixels", Range::openClosed(0, PixelFilter::MaxRadius)});
  f.checkUnused();
  PixelFilter filter(type, radius, a, b);
  // A filter must integrate to more than zero to be normalised (a Mitchell
  // filter with large B or C, say, need not).
  if (!(filter.integral1D() > 1e-3f * radius)) f.fail("type", "this " + name + " filter integrates to about zero or less; it cannot be normalised");
  return filter;
}

void readCamera(Params& root, Scene& scene, const LoadContext& ctx) {
  int width = 256, height = 256;
  PixelFilter filter;
  if (auto film = root.getChild("film")) {
    width = film->getInt("width", width);
    height = film->getInt("height", height);
    if (width <= 0) film->fail("width", "must be positive");
    if (height <= 0) film->fail("height", "must be positive");
    checkFilmMemory(*film, width, height);
    if (auto f = film->getChild("filter")) filter = readFilter(*f);
    film->checkUnused();
  }
  auto cam = root.getChild("camera");
  if (!cam) root.fail("camera", "is required");
  Vec3 pos = cam->requireVec3("position"), target = cam->requireVec3("look_at");
  Vec3 up = cam->getVec3("up", Vec3(0, 1, 0));
  float fov = cam->getFloat("fov", 40);
  std::string axis = cam->getChoice("fov_axis", "y", {"y", "x", "diagonal", "smaller", "larger"});
  std::string handedness = cam->getChoice("handedness", "right", {"right", "left"});
  cam->checkUnused();
  if (!(fov > 0 && fov < 180)) cam->fail("fov", "must be in (0, 180) degrees");
  fov = verticalFov(fov, axis, width, height);
  if (pos == target) cam->fail("look_at", "must differ from position");
  // A vector like [0, 1e-40, 0] has a direction a float cannot normalise.
  if (!(std::max({std::abs(up.x), std::abs(up.y), std::abs(up.z)}) >= 1e-18f))
    cam->fail("up", "is too short to have a direction (each component below 1e-18); give a unit vector");
  if (glm::length(glm::cross(target - pos, up)) == 0) cam->fail("up", "must not be parallel to the view direction");
  checkCoordinates(*cam, "position", pos * ctx.worldScale);
  scene.camera = Camera(pos * ctx.worldScale, target * ctx.worldScale, up, fov, width, height);
  if (handedness == "left") scene.camera.mirrorImage();
  scene.camera.setFilter(filter);
}

SceneFile loadFromNode(const YAML::Node& root, const std::string& path, bool deferWarnings = false, bool imported = false) {
  SceneFile out;
  out.path = path;
  out.scene = std::make_unique<Scene>();
  Scene& scene = *out.scene;
  Params p(root, path, "");
  LoadContext ctx;
  ctx.imported = imported;
  ctx.folder = std::filesystem::path(path).parent_path().string();
  ctx.worldScale = p.getFloat("world_scale", 1.f);
  if (std::string problem = worldScaleProblem(ctx.worldScale); !problem.empty()) p.fail("world_scale", problem);

  readCamera(p, scene, ctx);
  if (auto mats = p.getChild("materials")) {
    for (auto it = mats->node().begin(); it != mats->node().end(); ++it) {
      std::string name = it->first.as<std::string>();
      mats->has(name);  // mark as read
      Params mp(it->second, path, "materials." + name);
      if (!it->second.IsMap()) mp.fail("", "expected a mapping with a 'type'");
      ctx.materials[name] = scene.addMaterial(makeMaterial(mp, ctx.folder));
    }
    mats->checkUnused();
  }
  ctx.defaultMaterial = scene.addMaterial([&] {
    Params none(YAML::Node(YAML::NodeType::Map), path, "default material");
    return makeMaterial(none);
  }());
  // Objects (shapes defined once, in their own space) before the shapes whose
  // instances place them.
  if (auto objects = p.getChild("objects")) {
    for (auto it = objects->node().begin(); it != objects->node().end(); ++it) {
      std::string name = it->first.as<std::string>();
      objects->has(name);  // mark as read
      if (!it->second.IsSequence() || it->second.size() == 0) objects->fail(name, "expected a list of shapes");
      ctx.objects[name] = scene.addObject();
      for (Params& sp : objects->getList(name)) readShape(sp, scene, ctx, ctx.objects[name]);
    }
    objects->checkUnused();
  }
  for (Params& sp : p.getList("shapes")) readShape(sp, scene, ctx);
  for (Params& lp : p.getList("lights")) readLight(lp, scene, ctx);
  std::string selection = p.getChoice("light_selection", "power", {"power", "uniform"});
  if (auto s = p.getChild("sampler")) out.sampler = readSamplerSettings(*s);
  if (p.has("integrator")) {
    out.integrator = root["integrator"];
    if (!out.integrator.IsMap()) p.fail("integrator", "expected a mapping with a 'name'");
  }
  p.checkUnused();
  out.degenerateTriangles = ctx.degenerateTriangles;
  const LightSelection rule = selection == "power" ? LightSelection::Power : LightSelection::Uniform;
  scene.build(rule);
  // Environment and directional lights' powers depend on the scene's radius: known once it is built.
  for (LightSource& s : ctx.lights)
    if (s.light) {
      Color phi = s.light->power();
      s.power = double(std::max({phi.r, phi.g, phi.b}));
    }
  checkLightPowers(ctx, rule);
  if (deferWarnings) out.warnings = ctx.warnings;
  else
    for (const std::string& w : ctx.warnings) warn(w);
  return out;
}

}  // namespace

// A film too large for memory would otherwise fail with std::bad_alloc, after
// the scene is built. Per pixel (core/film.h): four dvec3 accumulators (sum,
// sum of squares, pass sum, pass sum of squares) and a 64-bit sample count;
// a splatting integrator's PassImage (one dvec3); and the float image written
// at the end. Integrators' own per-pixel data come on top.
std::string filmMemoryProblem(int width, int height) {
  const double bytesPerPixel = 5 * sizeof(glm::dvec3) + sizeof(uint64_t) + sizeof(Color);
  const double bytes = double(width) * double(height) * bytesPerPixel;
  const double limit = 0.9 * availableMemoryBytes();
  if (bytes <= limit) return "";
  char msg[256];
  std::snprintf(msg, sizeof msg,
                "a %d x %d film needs about %.3g GiB (%.0f bytes per pixel), more than 90%% of the %.1f GiB of "
                "memory available",
                width, height, bytes / (1 << 30), bytesPerPixel, limit / 0.9 / (1 << 30));
  return msg;
}

std::string worldScaleProblem(double s) {
  if (!(s > 0) || !std::isfinite(s)) return "must be positive and finite";
  // The scales the images are tested unchanged at (extremes_scale_test.cpp,
  // path_tracer_test.cpp): beyond them nothing says the image is right, and
  // it is not (at 2.3e-13 Embree rejects the rays; at 7e12 the squared
  // areas overflow), so they are refused rather than rendered.
  if (s < double(kMinWorldScale) || s > double(kMaxWorldScale)) {
    char msg[220];
    std::snprintf(msg, sizeof msg, "%g is outside [1e-4, 1e6], the scales lightbench's images are tested unchanged at "
                  "(docs/extremes.md)", s);
    return msg;
  }
  return "";
}

namespace {

void applyOverrides(YAML::Node& root, const YAML::Node& overrides) {
  if (!overrides || !overrides.IsMap()) return;
  for (auto it = overrides.begin(); it != overrides.end(); ++it) {
    std::string key = it->first.as<std::string>();
    if (it->second.IsMap() && root[key] && root[key].IsMap()) {
      // A fresh mapping of the same value nodes (YAML::Clone would reset their lines).
      YAML::Node merged(YAML::NodeType::Map);
      for (auto jt = root[key].begin(); jt != root[key].end(); ++jt) merged[jt->first] = jt->second;
      for (auto jt = it->second.begin(); jt != it->second.end(); ++jt) merged[jt->first.as<std::string>()] = jt->second;
      root[key] = merged;
    } else {
      root[key] = it->second;
    }
  }
}

// An imported scene: its warnings printed once it loads (or the first one an
// error under --strict), and errors the YAML loader finds in the translation re-thrown
// at the XML element they came from.
SceneFile loadImported(const std::string& path, const YAML::Node& overrides, const SceneLoadOptions& options) {
  ImportedScene imp = importScene(path);
  if (options.strict && !imp.warnings.empty()) {
    const ImportWarning& w = imp.warnings.front();
    throw ConfigError(path, w.line, w.element, w.message + " (--strict; " + std::to_string(imp.warnings.size()) +
                                                   " unsupported item(s) in all)");
  }
  YAML::Node description = YAML::Clone(imp.scene);
  // Not a clone: cloned nodes claim line 1, and errors found in the
  // translation must fall through to the XML lines below.
  YAML::Node root = imp.scene;
  applyOverrides(root, overrides);
  SceneFile out;
  try {
    out = loadFromNode(root, path, options.deferWarnings, true);
  } catch (const ConfigError& e) {
    if (e.line() > 0 || e.file() != path) throw;
    std::pair<std::string, int> best{"", 0};
    for (const auto& o : imp.origins) {
      const std::string& k = e.key();
      bool prefix = k.compare(0, o.first.size(), o.first) == 0 &&
                    (k.size() == o.first.size() || k[o.first.size()] == '.' || k[o.first.size()] == '[');
      if (prefix && o.first.size() > best.first.size()) best = o;
    }
    if (best.second == 0) throw;
    std::string what = e.what(), prefix = path + ": ";
    throw ConfigError(path, best.second, "", what.compare(0, prefix.size(), prefix) == 0 ? what.substr(prefix.size()) : what);
  }
  // The loader's own warnings about the translation ("file:0: shapes[3]: …")
  // get the line of the source element that shape came from.
  for (std::string& w : out.warnings) {
    std::string prefix = path + ":0: ";
    if (w.compare(0, prefix.size(), prefix) != 0) continue;
    std::string rest = w.substr(prefix.size());
    int line = 0;
    size_t best = 0;
    for (const auto& o : imp.origins)
      if (rest.compare(0, o.first.size(), o.first) == 0 && o.first.size() > best &&
          (rest.size() == o.first.size() || rest[o.first.size()] == ':' || rest[o.first.size()] == '.'))
        best = o.first.size(), line = o.second;
    if (line > 0) w = path + ":" + std::to_string(line) + ": " + rest;
  }
  // Only now: a scene refused gets its one error line, not warnings first.
  if (!options.quiet) {
    std::vector<std::string> imported;
    for (const ImportWarning& w : imp.warnings) imported.push_back(w.text(path));
    out.warnings.insert(out.warnings.begin(), imported.begin(), imported.end());
  }
  if (!options.deferWarnings) printSceneWarnings(out);
  out.description = description;
  out.sceneSpp = imp.sampleCount;
  out.sharedIntegratorKeys = imp.sharedIntegratorKeys;
  out.importWarnings = imp.warnings.size();
  return out;
}

}  // namespace

SceneFile loadScene(const std::string& path) { return loadScene(path, YAML::Node()); }

YAML::Node withSharedIntegratorKeys(const SceneFile& scene, const YAML::Node& params,
                                    const std::function<bool(const std::string& key)>& reads) {
  YAML::Node out(YAML::NodeType::Map);
  if (params && params.IsMap())
    for (auto it = params.begin(); it != params.end(); ++it) out[it->first] = it->second;
  if (scene.integrator && scene.integrator.IsMap())
    for (const std::string& key : scene.sharedIntegratorKeys)
      if (!out[key] && scene.integrator[key] && (!reads || reads(key))) out[key] = scene.integrator[key];
  return out;
}

SceneFile loadScene(const std::string& path, const YAML::Node& overrides, const SceneLoadOptions& options) {
  if (isImportedScenePath(path)) return loadImported(path, overrides, options);
  YAML::Node root = loadYamlFile(path);
  YAML::Node description = YAML::Clone(root);
  applyOverrides(root, overrides);
  SceneFile out = loadFromNode(root, path, options.deferWarnings);
  out.description = description;
  return out;
}

void printSceneWarnings(SceneFile& scene) {
  for (const std::string& w : scene.warnings) warn(w);
  scene.warnings.clear();
}

YAML::Node loadSceneDescription(const std::string& path) {
  return isImportedScenePath(path) ? importScene(path).scene : loadYamlFile(path);
}

SceneFile loadSceneFromString(const std::string& yaml, const std::string& virtualPath) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw malformedYaml(virtualPath, e);
  }
  checkMappings(root, virtualPath, "");
  return loadFromNode(root, virtualPath);
}

}  // namespace lb
