// The camera, film, sampler, pixel filter and integrator of a pbrt-v4 scene
// (see translator.h; defaults are pbrt-v4's, from its User's Guide).
#include <cmath>
#include <map>
#include "core/error.h"
#include "core/pbrt/translator.h"

namespace lb::pbrt {

// The CTM at Camera maps world to camera space; see import.h for the handedness.
void Translator::camera(const std::string& type, const ParamSet& ps, const Where& at) {
  cameraSeen_ = true;
  if (type != "perspective")
    throw ConfigError(at.file, at.line, at.column, "", "camera '" + type + "' is not supported (only perspective)");
  glm::dmat4 worldFromCamera = glm::inverse(gs_.ctm);
  glm::dmat3 r(worldFromCamera);
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(glm::length(r[c]) - 1) <= 1e-3))
      throw ConfigError(at.file, at.line, at.column, "", "the camera transform scales (each axis must keep unit length)");
  double fov = ps.getFloat("fov", 90);
  if (!(fov > 0 && fov < 180)) ps.fail(*ps.find("fov"), "must be in (0, 180) degrees");
  glm::dvec3 position(worldFromCamera[3]), forward = glm::normalize(r[2]), up = glm::normalize(r[1]),
      right = glm::normalize(r[0]);
  YAML::Node cam(YAML::NodeType::Map);
  cam["position"] = flowVec(position);
  cam["look_at"] = flowVec(position + forward * std::max(1.0, glm::length(position)));
  cam["up"] = flowVec(up);
  cam["fov"] = fov;
  cam["fov_axis"] = "smaller";
  // pbrt puts camera +x on the image's right; lightbench puts cross(forward, up) there.
  if (glm::dot(glm::cross(forward, up), right) < 0) cam["handedness"] = "left";
  for (const char* key : {"lensradius", "focaldistance"})
    if (ps.has(key)) {
      ps.getFloat(key, 0);
      if (std::string(key) == "lensradius" && ps.getFloat(key, 0) > 0)
        warn(at, "depth of field (lensradius > 0) not supported; rendered as a pinhole camera");
    }
  for (const char* key : {"frameaspectratio", "screenwindow", "shutteropen", "shutterclose"})
    if (const Param* p = ps.find(key)) warn(at, "parameter " + p->declaration() + " not supported; ignored");
  warnUnused(ps, at);
  out_.origins.emplace_back("camera", at.mainLine);
  root_["camera"] = cam;
}

void Translator::film(const std::string& type, const ParamSet& ps, const Where& at) {
  if (filmSeen_) throw ConfigError(at.file, at.line, at.column, "", "a second Film: a scene has one");
  filmSeen_ = true;
  if (type != "rgb") warn(at, "film '" + type + "' read as \"rgb\"");
  long w = ps.getInt("xresolution", 1280), h = ps.getInt("yresolution", 720);
  if (w <= 0) ps.fail(*ps.find("xresolution"), "must be positive");
  if (h <= 0) ps.fail(*ps.find("yresolution"), "must be positive");
  ps.getString("filename", "");  // lightbench names its output itself
  for (const char* key : {"cropwindow", "pixelbounds"})
    if (const Param* p = ps.find(key)) warn(at, "parameter " + p->declaration() + " not supported (use --crop); ignored");
  for (const char* key : {"iso", "exposuretime", "whitebalance", "sensor", "diagonal", "maxcomponentvalue", "savefp16"})
    if (const Param* p = ps.find(key)) warn(at, "parameter " + p->declaration() + " not supported; ignored");
  warnUnused(ps, at);
  YAML::Node f(YAML::NodeType::Map);
  f["width"] = w;
  f["height"] = h;
  out_.origins.emplace_back("film", at.mainLine);
  root_["film"] = f;
}

void Translator::sampler(const std::string& type, const ParamSet& ps, const Where& at) {
  samplerSeen_ = true;
  long spp = ps.getInt("pixelsamples", 16);
  if (spp <= 0) ps.fail(*ps.find("pixelsamples"), "must be positive");
  out_.sampleCount = uint64_t(spp);
  YAML::Node s(YAML::NodeType::Map);
  // pbrt-v4's samplers and lightbench's nearest (docs/rendering.md, Samplers).
  if (type == "independent") {
    s["type"] = "independent";
  } else if (type == "sobol" || type == "paddedsobol") {
    s["type"] = "sobol";
    if (type == "paddedsobol") warn(at, "read as lightbench's sobol (Owen-scrambled, padded per request)");
  } else if (type == "zsobol") {
    bool power2 = (spp & (spp - 1)) == 0;
    s["type"] = power2 ? "zsobol" : "sobol";
    if (power2) s["spp"] = spp;
    else warn(at, "zsobol needs a power-of-2 pixelsamples; read as sobol");
  } else if (type == "halton") {
    s["type"] = "halton";
  } else if (type == "stratified") {
    long x = ps.getInt("xsamples", 4), y = ps.getInt("ysamples", 4);
    if (x < 1 || y < 1) throw ConfigError(at.file, at.line, at.column, x < 1 ? "xsamples" : "ysamples", "must be at least 1");
    ps.getBool("jitter", true);
    if (x != y || x < 1 || x > 64) {
      warn(at, "stratified with xsamples != ysamples (or outside 1-64) read as independent");
      s["type"] = "independent";
    } else {
      s["type"] = "stratified";
      s["strata"] = x;
    }
    if (!ps.has("pixelsamples")) out_.sampleCount = uint64_t(x * y);
  } else {
    warn(at, "sampler '" + type + "' read as independent");
    s["type"] = "independent";
  }
  if (const Param* p = ps.find("randomization")) warn(at, "parameter " + p->declaration() + " not supported; lightbench's own scrambling is used");
  if (const Param* p = ps.find("seed")) warn(at, "parameter " + p->declaration() + " ignored (use --seed)");
  warnUnused(ps, at);
  out_.origins.emplace_back("sampler", at.mainLine);
  root_["sampler"] = s;
}

// pbrt-v4's filters (src/pbrt/filters.cpp) with its defaults; lightbench's
// have one radius for both axes (core/filter.h).
void Translator::pixelFilter(const std::string& type, const ParamSet& ps, const Where& at) {
  filterSeen_ = true;
  static const std::map<std::string, double> defaultRadius = {
      {"box", 0.5}, {"triangle", 2}, {"gaussian", 1.5}, {"mitchell", 2}, {"sinc", 4}};
  auto it = defaultRadius.find(type);
  YAML::Node f(YAML::NodeType::Map);
  if (it == defaultRadius.end()) {
    warn(at, "filter '" + type + "' not supported; a box of radius 0.5 is used");
    ps.markAllUsed();
    f["type"] = "box";
    filter_ = f;
    return;
  }
  double rx = ps.getFloat("xradius", it->second), ry = ps.getFloat("yradius", it->second);
  if (!(rx > 0 && ry > 0)) ps.fail(*ps.find(rx > 0 ? "yradius" : "xradius"), "must be positive");
  if (rx != ry) warn(at, "different x and y radii: lightbench's filters have one; the larger is used");
  double radius = std::max(rx, ry);
  static const std::map<std::string, std::string> names = {
      {"box", "box"}, {"triangle", "tent"}, {"gaussian", "gaussian"}, {"mitchell", "mitchell"}, {"sinc", "lanczos"}};
  f["type"] = names.at(type);
  f["radius"] = radius;
  if (type == "gaussian") f["sigma"] = ps.getFloat("sigma", 0.5);
  if (type == "mitchell") {
    f["b"] = ps.getFloat("B", 1.0 / 3);
    f["c"] = ps.getFloat("C", 1.0 / 3);
  }
  if (type == "sinc") f["tau"] = ps.getFloat("tau", 3);
  warnUnused(ps, at);
  out_.origins.emplace_back("film.filter", at.mainLine);
  filter_ = f;
}

// pbrt-v4's integrators → lightbench's; maxdepth counts bounces (import.h),
// so lightbench's max_depth is maxdepth + 1, whichever integrator runs.
void Translator::integrator(const std::string& type, const ParamSet& ps, const Where& at) {
  if (integratorSeen_) throw ConfigError(at.file, at.line, at.column, "", "a second Integrator: a scene has one");
  integratorSeen_ = true;
  static const std::map<std::string, std::string> names = {
      {"path", "path"},   {"volpath", "path"}, {"simplepath", "path"}, {"bdpt", "bdpt"},
      {"lightpath", "light"}, {"sppm", "sppm"}, {"mlt", "mlt"}};
  YAML::Node integ(YAML::NodeType::Map);
  auto it = names.find(type);
  integ["name"] = it == names.end() ? "path" : it->second;
  long depth = ps.getInt("maxdepth", 5);
  if (depth < 0) ps.fail(*ps.find("maxdepth"), "must be >= 0");
  integ["max_depth"] = depth + 1;
  out_.sharedIntegratorKeys.push_back("max_depth");
  if (type == "volpath" && at.line > 0) warn(at, "read as path (no participating media yet)");
  if (type == "sppm") {
    // pbrt-v4's SPPM (Hachisuka & Jensen 2009): radius is the initial radius,
    // alpha fixed at 2/3; -1 photons per iteration means one per pixel.
    long photons = ps.getInt("photonsperiteration", -1);
    if (photons > 0) integ["photons_per_pass"] = photons;
    // pbrt-v4's radius is absolute, default 1 (lightbench's default is relative to the scene).
    integ["initial_radius"] = ps.getFloat("radius", 1);
    integ["alpha"] = 2.0 / 3.0;
    if (const Param* p = ps.find("iterations")) warn(at, "parameter " + p->declaration() + " read as nothing: lightbench's spp (--spp) counts passes");
    ps.find("seed");
  }
  if (type == "path" || type == "volpath" || type == "bdpt") {
    if (const Param* p = ps.find("lightsampler"))
      if (!p->strings.empty() && p->strings[0] != "bvh")
        warn(at, "lightsampler '" + p->strings[0] + "': lightbench's light selection is set by light_selection");
    ps.find("lightsampler");
    if (ps.getBool("regularize", false)) warn(at, "regularize not supported; ignored");
  }
  if (it == names.end()) {
    warn(at, "integrator '" + type + "' has no lightbench counterpart; path is the default (--integrator chooses), its maxdepth is kept");
    ps.markAllUsed();
  }
  warnUnused(ps, at);
  if (at.line > 0) out_.origins.emplace_back("integrator", at.mainLine);
  root_["integrator"] = integ;
}

}  // namespace lb::pbrt
