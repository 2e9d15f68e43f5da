// The camera, film, sampler and integrator of a Mitsuba scene (see translator.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <vector>
#include "core/mitsuba/translator.h"
#include "core/sampler.h"

namespace lb::mitsuba {

// Mitsuba's integrator names → ours; max_depth counts segments in both
// (integrators/path_length.h), so it carries over whichever integrator runs.
void Translator::readIntegrator(pugi::xml_node n) {
  static const std::map<std::string, std::string> names = {
      {"path", "path"}, {"ptracer", "light"}, {"bdpt", "bdpt"}, {"sppm", "sppm"}, {"photonmapper", "photon"}};
  // Mitsuba 3 keeps the last <integrator>; a file holding two is a mistake to name, not to guess at.
  if (integratorSeen_) xml_.fail(n, "", "a second <integrator>: a scene has one");
  std::string type = xml_.attr(n, "type");
  Props p(xml_, n);
  integratorSeen_ = true;
  auto it = names.find(type);
  YAML::Node integ(YAML::NodeType::Map);
  integ["name"] = it == names.end() ? "path" : it->second;
  long depth = p.getInt("max_depth", -1);
  if (depth < -1) xml_.fail(n, "max_depth", "must be >= 0, or -1 for unlimited");
  if (depth == -1) {
    // Not every lightbench integrator can run unbounded paths (the photon methods cannot).
    depth = kUnlimitedDepth;
    xml_.warn(n, "max_depth unlimited (Mitsuba's default, or -1): approximated as " + std::to_string(kUnlimitedDepth) + " segments");
  }
  integ["max_depth"] = depth;
  out_.sharedIntegratorKeys.push_back("max_depth");
  if (type == "sppm") {
    // Mitsuba's SPPM settings have direct counterparts (Hachisuka & Jensen
    // 2009: photons per pass, initial radius, radius reduction alpha).
    if (p.has("photon_count")) integ["photons_per_pass"] = p.getInt("photon_count", 0);
    if (p.has("initial_radius")) integ["initial_radius"] = p.getFloat("initial_radius", 0);
    if (p.has("alpha")) integ["alpha"] = p.getFloat("alpha", 0);
  }
  if (it == names.end()) {
    // Its max_depth still defines the integral the scene asks for.
    xml_.warn(n, "integrator '" + type + "' has no lightbench counterpart; path is the default (--integrator chooses), its max_depth is kept");
    p.takeAll();
  }
  for (pugi::xml_node o : p.objects) xml_.warn(o, "not supported inside <integrator>; dropped");
  p.finish();
  origin("integrator", n);
  root_["integrator"] = integ;
}

// A pinhole camera. Mitsuba's camera looks along its local +z with +y up and
// image-right along local −x; lightbench's right is cross(forward, up), which
// is the same direction for a rotation, so images are not mirrored.
void Translator::readSensor(pugi::xml_node n) {
  if (sensorSeen_) xml_.fail(n, "", "a second <sensor>: lightbench renders one camera");
  sensorSeen_ = true;
  std::string type = xml_.attr(n, "type");
  if (type != "perspective") xml_.fail(n, "type", "sensor '" + type + "' is not supported (only 'perspective')");
  Props p(xml_, n);
  double fov = 0;
  std::string axis = p.getString("fov_axis", "x");
  for (char& c : axis) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (p.has("fov") && p.has("focal_length")) xml_.fail(n, "fov", "give fov or focal_length, not both");
  if (p.has("fov")) {
    fov = p.getFloat("fov", 0);
  } else {
    // A 35 mm film's diagonal over the focal length ("50mm", Mitsuba's default).
    std::string f = p.getString("focal_length", "50mm");
    double mm = std::strtod(f.c_str(), nullptr);
    if (!(mm > 0)) xml_.fail(n, "focal_length", "expected a length such as \"50mm\", got '" + f + "'");
    fov = glm::degrees(2 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2 * mm)));
    axis = "diagonal";
  }
  static const std::vector<std::string> axes = {"x", "y", "diagonal", "smaller", "larger"};
  if (std::find(axes.begin(), axes.end(), axis) == axes.end())
    xml_.fail(n, "fov_axis", "expected x, y, diagonal, smaller or larger, got '" + axis + "'");
  glm::dmat4 m = p.getTransform("to_world");
  if (glm::determinant(glm::dmat3(m)) < 0)
    xml_.fail(n, "to_world", "a mirroring camera transform is not supported (the image would be flipped)");
  for (int c = 0; c < 3; ++c)
    if (std::abs(glm::length(glm::dvec3(m[c])) - 1) > 1e-3)
      xml_.fail(n, "to_world", "a camera transform must not scale (Mitsuba refuses it too)");
  for (const char* clip : {"near_clip", "far_clip"})
    if (p.has(clip)) {
      p.getFloat(clip, 0);
      xml_.warn(n, std::string(clip) + " not supported; dropped (lightbench does not clip camera rays)");
    }
  bool film = false, sampler = false;
  for (pugi::xml_node o : p.objects) {
    std::string tag = o.name();
    // A second one would silently replace the first (issue 34, class 3), as a
    // second <integrator> did.
    if ((tag == "sampler" && sampler) || (tag == "film" && film))
      xml_.fail(o, "", "a second <" + tag + "> in one <sensor>: a sensor has one");
    if (tag == "sampler") {
      readSampler(o);
      sampler = true;
    } else if (tag == "film") {
      readFilm(o);
      film = true;
    } else {
      xml_.warn(o, "not supported inside <sensor>; dropped");
    }
  }
  // Mitsuba's defaults: a 768 × 576 HDR film with a Gaussian filter, 4 samples per pixel.
  if (!film) {
    YAML::Node f(YAML::NodeType::Map);
    f["width"] = 768;
    f["height"] = 576;
    root_["film"] = f;
    xml_.warn(n, "no <film>: Mitsuba's default 768 x 576 film, with a box filter instead of its Gaussian");
  }
  if (!sampler) out_.sampleCount = 4;
  p.finish();
  glm::dvec3 position(m[3]), forward = glm::normalize(glm::dvec3(m[2])), up = glm::normalize(glm::dvec3(m[1]));
  YAML::Node cam(YAML::NodeType::Map);
  cam["position"] = flowVec(position);
  // Far from the origin a unit step would lose the direction's precision in float.
  cam["look_at"] = flowVec(position + forward * std::max(1.0, glm::length(position)));
  cam["up"] = flowVec(up);
  cam["fov"] = fov;
  cam["fov_axis"] = axis;
  origin("camera", n);
  root_["camera"] = cam;
}

void Translator::readSampler(pugi::xml_node n) {
  std::string type = xml_.attr(n, "type");
  Props p(xml_, n);
  long count = p.getInt("sample_count", 4);
  if (count < 1 || uint64_t(count) > kMaxSpp)
    xml_.fail(n, "sample_count", "must be from 1 to " + std::to_string(kMaxSpp) + " (samples per pixel)");
  out_.sampleCount = uint64_t(count);
  YAML::Node s(YAML::NodeType::Map);
  if (type == "stratified") {
    s["type"] = "stratified";
    s["strata"] = std::clamp(int(std::lround(std::sqrt(double(count)))), 1, 64);
  } else {
    if (type != "independent")
      xml_.warn(n, "sampler '" + type + "' not supported; approximated as independent (the same expectation, other variance)");
    s["type"] = "independent";
  }
  if (type != "independent" && type != "stratified") p.takeAll();
  p.finish();
  origin("sampler", n);
  root_["sampler"] = s;
}

// <rfilter> as Mitsuba 0.6 and 3 define it (core/filter.h has the profiles):
// box (radius ½), tent (radius 1), gaussian (stddev ½, radius 4·stddev),
// mitchell (B, C ⅓, radius 2), catmullrom (Mitchell with B 0, C ½), lanczos
// (lobes 3, radius = lobes); a 0.6 file may give box's and tent's radius.
YAML::Node Translator::readFilter(pugi::xml_node o) {
  std::string type = xml_.attr(o, "type");
  Props p(xml_, o);
  YAML::Node f(YAML::NodeType::Map);
  if (type == "box" || type == "tent") {
    f["type"] = type;
    f["radius"] = p.getFloat("radius", type == "box" ? 0.5 : 1.0);
  } else if (type == "gaussian") {
    f["type"] = "gaussian";
    f["sigma"] = p.getFloat("stddev", 0.5);
  } else if (type == "mitchell" || type == "catmullrom") {
    f["type"] = "mitchell";
    f["b"] = type == "mitchell" ? p.getFloat("B", 1.0 / 3) : 0.0;
    f["c"] = type == "mitchell" ? p.getFloat("C", 1.0 / 3) : 0.5;
  } else if (type == "lanczos") {
    double lobes = double(p.getInt("lobes", 3));
    f["type"] = "lanczos";
    f["tau"] = lobes;
    f["radius"] = lobes;
  } else {
    xml_.warn(o, "reconstruction filter '" + type + "' not supported; a box filter is used (each sample counts in its own pixel)");
    p.takeAll();
    f["type"] = "box";
  }
  p.finish();
  return f;
}

void Translator::readFilm(pugi::xml_node n) {
  std::string type = xml_.attr(n, "type");
  Props p(xml_, n);
  YAML::Node film(YAML::NodeType::Map);
  film["width"] = p.getInt("width", 768);
  film["height"] = p.getInt("height", 576);
  if (type == "hdrfilm") {
    // The output encoding, not the estimate: lightbench writes float RGB EXR.
    for (const char* k : {"file_format", "pixel_format", "component_format"}) p.getString(k, "");
  } else {
    xml_.warn(n, "film '" + type + "' read as an HDR film: width and height kept, the rest dropped (lightbench writes EXR and PNG)");
    p.takeAll();
  }
  bool filterGiven = false;
  for (pugi::xml_node o : p.objects) {
    if (std::string(o.name()) != "rfilter") {
      xml_.warn(o, "not supported inside <film>; dropped");
      continue;
    }
    filterGiven = true;
    film["filter"] = readFilter(o);
  }
  if (!filterGiven) {  // Mitsuba's default (0.6 and 3): a Gaussian of σ ½ pixel, radius 4σ
    YAML::Node gaussian(YAML::NodeType::Map);
    gaussian["type"] = "gaussian";
    gaussian["sigma"] = 0.5;
    film["filter"] = gaussian;
  }
  p.finish();
  origin("film", n);
  root_["film"] = film;
}

}  // namespace lb::mitsuba
