#include "experiments/validate.h"
#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace lb {

namespace {
std::string size(int w, int h) { return std::to_string(w) + "×" + std::to_string(h); }

// Library messages can span lines; an error stays one line.
std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}
}  // namespace

Image readReferenceExr(const std::string& path, const KeyLocation& at) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw at.error("reference image not found: " + path);
  if (!fs::is_regular_file(path, ec)) throw at.error("reference " + path + " is not a file");
  Image image;
  try {
    image = readExr(path);
  } catch (const std::exception& ex) {
    throw at.error(oneLine(ex.what()));  // "cannot read PATH: " and OpenEXR's reason
  }
  // One NaN makes every metric against the reference NaN; refuse it rather
  // than log a run of nan rows.
  size_t nonFinite = 0;
  for (const Color& c : image.pixels) nonFinite += !(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b));
  if (nonFinite)
    throw at.error("reference " + path + " has " + std::to_string(nonFinite) + " non-finite (NaN or Inf) pixel" +
                   (nonFinite == 1 ? "" : "s") + " of " + std::to_string(image.pixels.size()));
  return image;
}

CheckedExperiment validateExperiment(const Experiment& e) {
  CheckedExperiment checked;
  for (const ExperimentScene& s : e.scenes) {
    // Warnings wait until every scene, crop and reference is accepted.
    SceneLoadOptions deferred;
    deferred.deferWarnings = true;
    SceneFile sf = loadScene(s.path, s.overrides, deferred);
    int w = sf.scene->camera.width(), h = sf.scene->camera.height();
    Image given, variance;
    if (!s.reference.file.empty()) {
      given = readReferenceExr(s.reference.file, s.referenceAt);
      if (given.width != w || given.height != h)
        throw s.referenceAt.error("reference is " + size(given.width, given.height) + ", the scene renders " + size(w, h));
      if (!s.reference.varianceFile.empty()) {
        variance = readReferenceExr(s.reference.varianceFile, s.referenceAt);
        if (variance.width != w || variance.height != h)
          throw s.referenceAt.error("reference variance is " + size(variance.width, variance.height) +
                                    ", the reference " + size(w, h));
        for (const Color& c : variance.pixels)
          if (c.r < 0 || c.g < 0 || c.b < 0)
            throw s.referenceAt.error("reference variance " + s.reference.varianceFile + " has negative values");
      }
    } else if (!s.reference.scene.empty()) {
      // Loaded only to learn its resolution: a mismatch would otherwise show
      // only after the reference had rendered.
      SceneFile rf = loadScene(s.reference.scene, s.resolution, deferred);  // its warnings come when it renders
      int rw = rf.scene->camera.width(), rh = rf.scene->camera.height();
      if (rw != w || rh != h)
        throw s.referenceAt.error("the reference scene renders " + size(rw, rh) + ", the scene renders " + size(w, h) +
                                  " (give the experiment scene a `resolution`)");
    }
    if (!s.crop.empty() && (s.crop.x1 > w || s.crop.y1 > h))
      throw s.cropAt.error("[" + std::to_string(s.crop.x0) + ", " + std::to_string(s.crop.y0) + ", " +
                           std::to_string(s.crop.x1) + ", " + std::to_string(s.crop.y1) + "] reaches beyond the " +
                           size(w, h) + " image of " + s.name);
    checked.scenes.push_back(std::move(sf));
    checked.givenReferences.push_back(std::move(given));
    checked.givenVariances.push_back(std::move(variance));
  }
  for (SceneFile& sf : checked.scenes) printSceneWarnings(sf);
  return checked;
}

}  // namespace lb
