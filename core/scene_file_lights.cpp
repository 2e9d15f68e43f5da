// The `lights:` of a YAML scene, and the check of their powers once the scene
// is built (scene_file_parts.h).
#include "core/scene_file_parts.h"
#include "core/image_input.h"
#include "core/memory.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include "core/lights/directional_light.h"
#include "core/lights/environment_light.h"
#include "core/lights/environment_map_light.h"
#include "core/image.h"
#include "core/lights/point_light.h"
#include "core/lights/spot_light.h"

namespace lb::scene_file {

// Light selection weighs each light by its power (core/light_sampler.h). A
// finite input can overflow it — a point light of 1e38 (power 4π·I), a
// constant environment of 1e38 over the scene's bounding sphere (4π²r²·L) —
// and a light chosen with probability NaN or 0 rendered black with no NaN
// counted (issue 34). Checked once the scene is built (an environment's or a
// directional light's power depends on the scene's radius), naming the key.
// The lights' powers together, in double, emitting shapes included: a light
// subpath's starting throughput Le / (selection pmf · pdf) is the lights'
// total power under selection by power, and the light count times the
// brightest light's under uniform selection; three point lights of 1e37
// passed the per-light check and overflowed it together. Blamed on the
// brightest light's key.
void checkLightPowers(LoadContext& ctx, LightSelection selection) {
  for (LightSource& s : ctx.lights) {
    if (!s.light) continue;  // an emitting shape: checked in readShape
    Color phi = s.light->power();
    if (!(std::isfinite(phi.r) && std::isfinite(phi.g) && std::isfinite(phi.b) && std::isfinite(luminance(phi))))
      s.params.fail(s.key, "the light's power (its emitted flux) is beyond a float's range; lower it");
  }
  double total = 0, brightest = 0;
  LightSource* brightestSource = nullptr;
  for (LightSource& s : ctx.lights) {
    total += s.power;
    if (s.power >= brightest) brightest = s.power, brightestSource = &s;
  }
  double throughput = selection == LightSelection::Power ? total : brightest * double(ctx.lights.size());
  if (brightestSource && !(throughput <= double(std::numeric_limits<float>::max())))
    brightestSource->params.fail(brightestSource->key,
                                 selection == LightSelection::Power
                                     ? "the lights' total power (their emitted flux, summed) is beyond a float's range, "
                                       "which a light path's throughput must hold; lower it"
                                     : "the brightest light's power times the number of lights (uniform selection) is "
                                       "beyond a float's range, which a light path's throughput must hold; lower it");
}

static void addLight(Scene& scene, LoadContext& ctx, Params& p, const std::string& key, std::unique_ptr<Light> light) {
  ctx.lights.push_back({light.get(), p, key});
  scene.addLight(std::move(light));
}

Color nonNegative(Params& p, const std::string& key, Color fallback) {
  Color c = p.getColor(key, fallback);
  if (glm::any(glm::lessThan(c, Color(0.f)))) p.fail(key, "must not be negative");
  return c;
}

// A point or spot light's intensity times s²: world_scale leaves the image
// unchanged. A finite intensity can overflow a float once scaled (1e30 at
// world_scale 1e6 is 1e42), which would render black: refused instead.
Color scaledIntensity(Params& p, float s) {
  Color I = nonNegative(p, "intensity", Color(1.f));
  double largest = double(std::max({I.r, I.g, I.b})) * double(s) * double(s);
  // (Its power, 4π times this, is checked with every light's: checkLightPowers.)
  if (!(largest <= double(std::numeric_limits<float>::max()))) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "%g times world_scale² (%g²) is %g, beyond a float's range", double(std::max({I.r, I.g, I.b})),
                  double(s), largest);
    p.fail("intensity", msg);
  }
  return I * s * s;
}

void readLight(Params& p, Scene& scene, LoadContext& ctx) {
  std::string type = p.getChoice("type", "", {"point", "spot", "directional", "environment"});
  float s = ctx.worldScale;
  if (type == "point") {
    Vec3 pos = p.requireVec3("position") * s;
    checkCoordinates(p, "position", pos);
    addLight(scene, ctx, p, "intensity", std::make_unique<PointLight>(pos, scaledIntensity(p, s)));
  } else if (type == "spot") {
    Vec3 pos = p.requireVec3("position") * s;
    checkCoordinates(p, "position", pos);
    Vec3 target = p.requireVec3("look_at") * s;
    if (target == pos) p.fail("look_at", "must differ from position");
    float cone = p.getFloat("cone_angle", 30), start = p.getFloat("falloff_start", cone * 0.8f);
    if (!(cone > 0 && cone < 180)) p.fail("cone_angle", "must be in (0, 180) degrees");
    if (!(start >= 0 && start <= cone)) p.fail("falloff_start", "must be in [0, cone_angle]");
    addLight(scene, ctx, p, "intensity", std::make_unique<SpotLight>(pos, target - pos, scaledIntensity(p, s), cone, start));
  } else if (type == "directional") {
    Vec3 dir = p.requireVec3("direction");
    if (glm::length(dir) == 0) p.fail("direction", "must not be zero");
    addLight(scene, ctx, p, "irradiance", std::make_unique<DirectionalLight>(dir, nonNegative(p, "irradiance", Color(1.f))));
  } else if (p.has("file")) {
    // An HDR lat-long map (core/lights/environment_map_light.h).
    if (p.has("radiance")) p.fail("radiance", "give radiance (constant) or file (a map), not both");
    std::string file = p.requireString("file");
    const std::filesystem::path full = std::filesystem::path(ctx.folder) / file;
    std::error_code ec;
    // A directory, FIFO or device would be read forever or not at all.
    if (!std::filesystem::is_regular_file(full, ec)) p.fail("file", "not a regular file: " + full.string());
    Image map;
    try {
      // Any format read for textures; an integer one (a PNG, a JPEG) is sRGB.
      map = readImageFile(full.string(), true).rgb;
    } catch (const std::exception& e) {
      p.fail("file", e.what());
    }
    float brightest = 0;
    for (size_t i = 0; i < map.pixels.size(); ++i) {
      const Color& c = map.pixels[i];
      // Each channel alone: a sum of finite texels of 3e38 overflowed and
      // called them non-finite.
      if (!(c.r >= 0 && c.g >= 0 && c.b >= 0 && std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)))
        p.fail("file", "the map has a negative or non-finite texel, at (" + std::to_string(i % size_t(map.width)) +
                           ", " + std::to_string(i / size_t(map.width)) + ")");
      brightest = std::max({brightest, c.r, c.g, c.b});
    }
    float scale = p.getFloat("scale", 1.f);
    if (!(scale >= 0)) p.fail("scale", "must not be negative");
    // The radiance a ray sees is texel × scale: a finite map and scale whose
    // product overflows gave every sample NaN (issue 34).
    if (!(double(brightest) * scale <= double(std::numeric_limits<float>::max()))) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "the brightest texel (%g) times scale (%g) is beyond a float's range",
                    double(brightest), double(scale));
      p.fail("scale", msg);
    }
    // rotate_y (degrees about +y), or a 3×3 orthogonal `rotation`, row by row.
    Mat3 toWorld = Mat3(glm::rotate(Mat4(1.f), glm::radians(p.getFloat("rotate_y", 0.f)), Vec3(0, 1, 0)));
    if (p.has("rotation")) {
      if (p.has("rotate_y")) p.fail("rotation", "give rotate_y or rotation, not both");
      std::vector<float> r = p.getFloatList("rotation", 9);
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) toWorld[col][row] = r[size_t(3 * row + col)];
      Mat3 e = glm::transpose(toWorld) * toWorld - Mat3(1.f);
      float worst = 0;
      for (int i = 0; i < 3; ++i) worst = std::max({worst, std::abs(e[i].x), std::abs(e[i].y), std::abs(e[i].z)});
      if (!(worst < 1e-4f)) p.fail("rotation", "must be orthogonal (a rotation, possibly mirrored): RᵀR differs from I by " + std::to_string(worst));
    }
    bool importance = p.getChoice("sampling", "importance", {"importance", "uniform"}) == "importance";
    addLight(scene, ctx, p, p.has("scale") ? "scale" : "file",
             std::make_unique<EnvironmentMapLight>(std::move(map), scale, toWorld, importance));
  } else {
    addLight(scene, ctx, p, "radiance", std::make_unique<EnvironmentLight>(nonNegative(p, "radiance", Color(1.f))));
  }
  p.checkUnused();
}


}  // namespace lb::scene_file
