#pragma once
// Reads a scene from YAML (format: README "Scene files"). Every key is checked:
// unknown keys, wrong types, non-finite numbers and non-physical values are
// ConfigErrors naming file, line and key.
#include <memory>
#include <string>
#include "core/sampler.h"
#include "core/scene.h"

namespace lb {

struct SceneFile {
  std::unique_ptr<Scene> scene;
  std::string path;
  YAML::Node integrator;  // the scene's `integrator:` mapping (name + parameters), may be null
  SamplerSettings sampler;
  size_t degenerateTriangles = 0;
};

SceneFile loadScene(const std::string& path);
// The same with top-level keys replaced (e.g. `film: {width: 64, height: 64}`);
// errors still name the scene file (lines of replaced keys are approximate).
SceneFile loadScene(const std::string& path, const YAML::Node& overrides);
// For tests: the same from text; relative mesh paths resolve against `virtualPath`'s folder.
SceneFile loadSceneFromString(const std::string& yaml, const std::string& virtualPath);

}  // namespace lb
