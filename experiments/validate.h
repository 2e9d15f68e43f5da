#pragma once
// Every input of an experiment checked before anything renders or any file is
// written, so a bad input costs seconds and leaves no run folder: each scene
// loads (with its overrides), each given reference is a readable EXR of the
// scene's resolution with finite pixels, each reference scene renders at that
// resolution, each crop lies inside the image. (Integrator names and
// parameters are checked earlier, by loadExperiment.) Errors name the
// experiment file, line and key; a scene's own errors name the scene file.
#include <string>
#include <vector>
#include "core/image.h"
#include "core/scene_loader.h"
#include "experiments/experiment.h"

namespace lb {

struct CheckedExperiment {
  std::vector<SceneFile> scenes;       // as the runs use them, one per experiment scene
  std::vector<Image> givenReferences;  // the image of a `reference: {file: …}`, else empty
  std::vector<Image> givenVariances;   // its `variance`, else empty
};

CheckedExperiment validateExperiment(const Experiment& experiment);

// A reference EXR read and checked (a regular file, readable, finite pixels);
// every failure is a ConfigError at `at`.
Image readReferenceExr(const std::string& path, const KeyLocation& at);

}  // namespace lb
