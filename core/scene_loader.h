#pragma once
// Reads a scene from YAML (format: README "Scene files"), or from Mitsuba XML
// (a path ending in .xml, translated by core/mitsuba/import.h into the same
// description). Every key is checked: unknown keys, wrong types, non-finite
// numbers and non-physical values are ConfigErrors naming file, line and key.
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "core/sampler.h"
#include "core/scene.h"

namespace lb {

struct SceneFile {
  std::unique_ptr<Scene> scene;
  std::string path;
  YAML::Node integrator;  // the scene's `integrator:` mapping (name + parameters), may be null
  SamplerSettings sampler;
  size_t degenerateTriangles = 0;
  YAML::Node description;  // the scene as built, in lightbench's YAML (an XML scene's translation)
  uint64_t sceneSpp = 0;   // samples per pixel the file asks for (Mitsuba's sample_count), 0 if none
  // Integrator keys that define the integral (Mitsuba's max_depth): they apply
  // to whichever integrator renders, not only to the one the file names.
  std::vector<std::string> sharedIntegratorKeys;
  size_t importWarnings = 0;
  // With SceneLoadOptions::deferWarnings, the warnings the loader would have
  // printed; the caller prints them once it has accepted the whole input
  // (printSceneWarnings), so a refused one is one error line (issue 34).
  std::vector<std::string> warnings;
};

struct SceneLoadOptions {
  bool strict = false;  // an unsupported element of an imported scene is an error, not a warning
  bool quiet = false;   // an imported scene's warnings are not printed (an earlier load printed them)
  bool deferWarnings = false;  // kept in SceneFile::warnings instead of printed
};

// Prints a scene's deferred warnings ("warning: ..."), once.
void printSceneWarnings(SceneFile& scene);

// An integrator's parameters for rendering `scene`: `params`, plus the scene's
// shared integrator keys (an imported scene's max_depth) that `params` does
// not set itself and the integrator reads (`reads`; without it, every key):
// the depth defines the integral the scene asks for, so it holds for every
// integrator that has a depth, and an integrator without one (direct) still
// renders the scene. Entries are shared with `params`, not cloned (errors
// keep their lines).
YAML::Node withSharedIntegratorKeys(const SceneFile& scene, const YAML::Node& params,
                                    const std::function<bool(const std::string& key)>& reads = {});

// A `sampler:` mapping (type, strata, spp), in a scene or an experiment's configuration.
class Params;
SamplerSettings readSamplerSettings(Params& p);

SceneFile loadScene(const std::string& path);
// The same with top-level keys replaced (e.g. `film: {width: 64, height: 64}`);
// errors still name the scene file (lines of replaced keys are approximate).
SceneFile loadScene(const std::string& path, const YAML::Node& overrides, const SceneLoadOptions& options = {});
// The scene's description without building it (YAML as written, XML
// translated): what a reference's key hashes.
YAML::Node loadSceneDescription(const std::string& path);
// For tests: the same from text; relative mesh paths resolve against `virtualPath`'s folder.
SceneFile loadSceneFromString(const std::string& yaml, const std::string& virtualPath);
// "" if a width x height film fits in the memory available, else why not
// (with the estimate); checked for the scene's film and an experiment's
// `resolution` before anything is allocated.
std::string filmMemoryProblem(int width, int height);
// "" if `s` can scale a scene, else why not: s must be in [1e-4, 1e6], the
// scales at which every integrator's image is tested unchanged. Beyond them
// (long before s³ leaves a float's range) rays, areas and intensities break:
// transforms cannot be inverted in float, emitters have zero area, lights
// overflow to Inf or Embree rejects the rays. Checked where world_scale is
// given (scene key, --world-scale, an experiment's world_scale), so the
// message names it.
inline constexpr float kMinWorldScale = 1e-4f, kMaxWorldScale = 1e6f;
std::string worldScaleProblem(double s);

}  // namespace lb
