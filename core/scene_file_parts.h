#pragma once
// The YAML scene reader's parts (scene_loader.cpp reads the file and the
// camera, scene_file_shapes.cpp the shapes, scene_file_lights.cpp the lights):
// what they share while one file loads. Internal to core/; the interface is
// scene_loader.h.
#include <map>
#include <string>
#include <vector>
#include "core/params.h"
#include "core/scene.h"
#include "core/light_sampler.h"

namespace lb::scene_file {

// A light as its file gave it, for checks that need the built scene.
struct LightSource {
  const Light* light;  // null for an emitting shape (its light is built with the scene)
  Params params;
  std::string key;     // the key its power comes from
  double power = 0;    // its largest channel's power, in double (set once known)
};

struct LoadContext {
  std::string folder;
  float worldScale = 1;
  std::map<std::string, int> materials;
  std::map<std::string, int> objects;  // `objects:` by name, as Scene::addObject numbered them
  int defaultMaterial = -1;
  size_t degenerateTriangles = 0;
  std::vector<LightSource> lights;
  // Printed only once the whole scene is accepted (issue 34, class 8): a
  // scene refused later gets its one error line, not warnings first.
  std::vector<std::string> warnings;
  // An imported scene (Mitsuba, pbrt): a shape whose every triangle is
  // degenerate is dropped with a warning, as those renderers show it
  // (nothing), instead of the YAML loader's error.
  bool imported = false;
};

// Embree takes no ray whose origin has a coordinate beyond 1.844e18
// (FLT_LARGE: an assertion, exit 134), and rays start at the camera, the
// lights and every surface, after transforms and world_scale. A tenth of
// that leaves room for the offsets and an infinite light's disc around the
// scene (issue 34: a point light at 2e18 aborted).
constexpr float kMaxCoordinate = 1e17f;
// Refuses a point beyond ±kMaxCoordinate, naming `key` (scene_loader.cpp).
void checkCoordinates(Params& p, const std::string& key, const Vec3& point);
// The lights' powers, one by one and together (scene_file_lights.cpp).
void checkLightPowers(LoadContext& ctx, LightSelection selection);
// A colour key that must not be negative.
Color nonNegative(Params& p, const std::string& key, Color fallback);
// One entry of `shapes:` (scene_file_shapes.cpp) or `lights:` (scene_file_lights.cpp).
// With an `object` (an id from Scene::addObject), a shape of `objects:`,
// in the object's own space: world_scale is its instances', and it cannot emit.
void readShape(Params& p, Scene& scene, LoadContext& ctx, int object = -1);
void readLight(Params& p, Scene& scene, LoadContext& ctx);

}  // namespace lb::scene_file
