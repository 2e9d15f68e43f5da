#include "core/scene_loader.h"
#include "core/memory.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include "core/bsdfs/material_factory.h"
#include "core/lights/directional_light.h"
#include "core/lights/environment_light.h"
#include "core/lights/environment_map_light.h"
#include "core/image.h"
#include "core/lights/point_light.h"
#include "core/lights/spot_light.h"
#include "core/mesh_io.h"
#include "core/mitsuba/import.h"

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

namespace {

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
  int defaultMaterial = -1;
  size_t degenerateTriangles = 0;
  std::vector<LightSource> lights;
  // Printed only once the whole scene is accepted (issue 34, class 8): a
  // scene refused later gets its one error line, not warnings first.
  std::vector<std::string> warnings;
};

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

// Embree takes no ray whose origin has a coordinate beyond 1.844e18
// (FLT_LARGE: an assertion, exit 134), and rays start at the camera, the
// lights and every surface, after transforms and world_scale. A tenth of
// that leaves room for the offsets and an infinite light's disc around the
// scene (issue 34: a point light at 2e18 aborted).
constexpr float kMaxCoordinate = 1e17f;
void checkCoordinates(Params& p, const std::string& key, const Vec3& point) {
  if (!(std::max({std::abs(point.x), std::abs(point.y), std::abs(point.z)}) <= kMaxCoordinate))
    p.fail(key, "lies beyond ±1e17 (after transforms and world_scale): rays start there, and Embree traces none "
                "from beyond ±1.8e18");
}

void addLight(Scene& scene, LoadContext& ctx, Params& p, const std::string& key, std::unique_ptr<Light> light) {
  ctx.lights.push_back({light.get(), p, key});
  scene.addLight(std::move(light));
}

// transform: {matrix: 16 numbers, row by row} (as Mitsuba writes it), or
// {scale, rotate_x, rotate_y, rotate_z, translate}, applied in that order.
Mat4 readMatrix(Params& t) {
  const YAML::Node n = t.node()["matrix"];
  t.has("matrix");
  if (!n.IsSequence() || n.size() != 16) t.fail("matrix", "expected 16 numbers, row by row");
  for (const char* other : {"scale", "rotate_x", "rotate_y", "rotate_z", "translate"})
    if (t.has(other)) t.fail(other, "cannot be combined with matrix");
  t.checkUnused();
  Mat4 m(1.f);
  for (int i = 0; i < 16; ++i) {
    float v = 0;
    try {
      v = n[i].as<float>();
    } catch (const YAML::Exception&) {
      t.fail("matrix", "expected 16 numbers, row by row");
    }
    if (!std::isfinite(v)) t.fail("matrix", "must be finite");
    m[i % 4][i / 4] = v;  // glm is column-major
  }
  if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
    t.fail("matrix", "the last row must be 0 0 0 1 (an affine transform)");
  return m;
}

Mat4 readTransform(Params& shape, const LoadContext& ctx) {
  Mat4 m(1.f);
  if (auto t = shape.getChild("transform"); t && t->has("matrix")) {
    m = readMatrix(*t);
  } else if (t) {
    Vec3 scale(1.f);
    if (t->has("scale")) {
      const YAML::Node n = t->node()["scale"];
      scale = n.IsScalar() ? Vec3(t->getFloat("scale", 1)) : t->getVec3("scale", Vec3(1.f));
    }
    float rx = t->getFloat("rotate_x", 0), ry = t->getFloat("rotate_y", 0), rz = t->getFloat("rotate_z", 0);
    Vec3 translate = t->getVec3("translate", Vec3(0.f));
    t->checkUnused();
    if (scale.x == 0 || scale.y == 0 || scale.z == 0) t->fail("scale", "makes the transform non-invertible");
    m = glm::translate(Mat4(1.f), translate);
    m = glm::rotate(m, glm::radians(rz), Vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(ry), Vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rx), Vec3(1, 0, 0));
    m = glm::scale(m, scale);
  }
  return glm::scale(Mat4(1.f), Vec3(ctx.worldScale)) * m;
}

TriangleMesh rectangleMesh() {
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  return m;
}

// The unit disc at z = 0 facing +z, as a regular polygon of `segments` sides
// (area (n/2)·sin(2π/n), 0.01 % short of π at 256), uv = (r, φ/2π) as
// Mitsuba's disk; each fan triangle has its own centre vertex, so that φ is
// continuous within it.
TriangleMesh diskMesh(int segments) {
  TriangleMesh m;
  for (int i = 0; i < segments; ++i) {
    float phi0 = 2 * Pi * i / segments, phi1 = 2 * Pi * (i + 1) / segments;
    unsigned b = unsigned(m.positions.size());
    m.positions.push_back(Vec3(0.f));
    m.positions.push_back(Vec3(std::cos(phi0), std::sin(phi0), 0));
    m.positions.push_back(Vec3(std::cos(phi1), std::sin(phi1), 0));
    m.uvs.push_back(Vec2(0, (i + 0.5f) / segments));
    m.uvs.push_back(Vec2(1, float(i) / segments));
    m.uvs.push_back(Vec2(1, float(i + 1) / segments));
    m.triangles.push_back({b, b + 1, b + 2});
  }
  return m;
}

// [-1,1]³ as Mitsuba's cube: 24 vertices, each face mapped onto [0,1]² of
// texture space, windings outward (the geometric normal follows the winding).
TriangleMesh boxMesh() {
  TriangleMesh m;
  m.positions = {{1, -1, -1}, {1, -1, 1},  {-1, -1, 1}, {-1, -1, -1},  // -y
                 {1, 1, -1},  {-1, 1, -1}, {-1, 1, 1},  {1, 1, 1},     // +y
                 {1, -1, -1}, {1, 1, -1},  {1, 1, 1},   {1, -1, 1},    // +x
                 {1, -1, 1},  {1, 1, 1},   {-1, 1, 1},  {-1, -1, 1},   // +z
                 {-1, -1, 1}, {-1, 1, 1},  {-1, 1, -1}, {-1, -1, -1},  // -x
                 {1, 1, -1},  {1, -1, -1}, {-1, -1, -1}, {-1, 1, -1}}; // -z
  for (unsigned face = 0; face < 6; ++face) {
    unsigned b = 4 * face;
    m.triangles.push_back({b, b + 1, b + 2});
    m.triangles.push_back({b + 3, b, b + 2});
    for (Vec2 uv : {Vec2(0, 1), Vec2(1, 1), Vec2(1, 0), Vec2(0, 0)}) m.uvs.push_back(uv);
  }
  return m;
}

void readShape(Params& p, Scene& scene, LoadContext& ctx) {
  std::string type = p.getChoice("type", "", {"mesh", "sphere", "rectangle", "box", "disk"});
  // A material by name ("none": an absorber), else an error at `key` of `at`.
  auto materialNamed = [&](Params& at, const std::string& key, const std::string& name) {
    if (name == "none") return -1;
    auto it = ctx.materials.find(name);
    if (it == ctx.materials.end()) {
      std::vector<std::string> names;
      for (auto& kv : ctx.materials) names.push_back(kv.first);
      std::string hint = closestMatch(name, names);
      at.fail(key, "unknown material '" + name + "'" + (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
    }
    return it->second;
  };
  int material = ctx.defaultMaterial;
  if (p.has("material")) material = materialNamed(p, "material", p.getString("material", ""));
  std::vector<int> triangleMaterials;
  Emission emission;
  emission.radiance = p.getColor("emission", Color(0.f));
  if (glm::any(glm::lessThan(emission.radiance, Color(0.f)))) p.fail("emission", "must not be negative");
  emission.twoSided = p.getBool("two_sided", false);

  Shape shape;
  if (type == "sphere") {
    Sphere s;
    s.center = p.getVec3("center", Vec3(0.f)) * ctx.worldScale;
    s.radius = p.getFloat("radius", 1.f) * ctx.worldScale;
    s.flipNormals = p.getBool("flip_normals", false);
    if (!(s.radius > 0) || !std::isfinite(s.radius)) p.fail("radius", "must be positive");
    shape = Shape::sphere(s);
  } else {
    Mat4 toWorld = readTransform(p, ctx);
    // Computed in double: a float determinant of 1e90 is Inf, of 1e-90 zero,
    // and the message would say "not invertible" without saying why.
    double det = std::abs(glm::determinant(glm::dmat4(toWorld)));
    if (!(det >= double(std::numeric_limits<float>::min()) && det <= double(std::numeric_limits<float>::max()))) {
      char msg[220];
      std::snprintf(msg, sizeof msg, "scale (times world_scale) changes volumes by a factor of %g, beyond a float's "
                    "range: the transform cannot be inverted in float (keep each axis's scale within about "
                    "[2.3e-13, 6.9e12])", det);
      p.fail("transform", msg);
    }
    TriangleMesh mesh;
    size_t dropped = 0;
    if (type == "mesh") {
      std::string file = p.requireString("file");
      bool smooth = p.getBool("smooth_normals", false);
      // Flat shading: the file's vertex normals are ignored (Mitsuba's face_normals).
      bool faceNormals = p.getBool("face_normals", false);
      if (smooth && faceNormals) p.fail("face_normals", "cannot be combined with smooth_normals");
      std::filesystem::path full = std::filesystem::path(ctx.folder) / file;
      try {
        MeshLoadResult r = loadMesh(full.string(), toWorld, smooth);
        mesh = std::move(r.mesh);
        if (faceNormals) mesh.normals.clear();
        dropped = r.degenerateTriangles;
      } catch (const std::runtime_error& e) {
        p.fail("file", e.what());
      }
      // Per-group materials: `materials: {usemtl name: material}`; groups not
      // named take `material` (one mesh, several materials, no splitting).
      if (auto groups = p.getChild("materials")) {
        if (mesh.groupNames.empty())
          p.fail("materials", "the file has no usemtl groups to give materials to (use material)");
        if (!mesh.groupsUnmatched.empty()) p.fail("materials", mesh.groupsUnmatched);
        std::vector<int> byGroup(mesh.groupNames.size(), material);
        for (auto it = groups->node().begin(); it != groups->node().end(); ++it) {
          std::string group = it->first.as<std::string>();
          auto g = std::find(mesh.groupNames.begin(), mesh.groupNames.end(), group);
          if (g == mesh.groupNames.end()) {
            std::string hint = closestMatch(group, mesh.groupNames);
            groups->fail(group, "no usemtl group '" + group + "' in " + file + (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
          }
          byGroup[size_t(g - mesh.groupNames.begin())] = materialNamed(*groups, group, groups->getString(group, ""));
        }
        for (int g : mesh.triangleGroups) triangleMaterials.push_back(byGroup[size_t(g)]);
        if (triangleMaterials.size() != mesh.triangles.size())
          p.fail("materials", "internal: " + std::to_string(triangleMaterials.size()) + " group entries for " +
                                  std::to_string(mesh.triangles.size()) + " triangles");
      }
    } else {
      if (type == "disk") {
        int segments = p.getInt("segments", 256);
        if (segments < 3 || segments > 65536) p.fail("segments", "must be in [3, 65536]");
        mesh = diskMesh(segments);
      } else {
        mesh = type == "box" ? boxMesh() : rectangleMesh();
      }
      dropped = transformMesh(mesh, toWorld);
    }
    // The geometric normal follows the winding (core/shape.cpp).
    if (p.getBool("flip_normals", false)) {
      for (auto& t : mesh.triangles) std::swap(t.y, t.z);
      for (Vec3& n : mesh.normals) n = -n;
    }
    // An all-degenerate shape is an error (one line), not a warning and an error.
    if (mesh.triangles.empty()) {
      if (!isBlack(emission.radiance)) p.fail("emission", "emitter has zero area (every triangle is degenerate)");
      p.fail(type == "mesh" ? "file" : "transform", "shape has zero area (every triangle is degenerate)");
    }
    if (dropped) {
      ctx.warnings.push_back(p.file() + ":" + std::to_string(p.line()) + ": " + p.context() + ": skipped " +
                             std::to_string(dropped) + " degenerate (zero-area) triangle(s)");
      ctx.degenerateTriangles += dropped;
    }
    shape = Shape::mesh(std::move(mesh));
  }
  if (!isBlack(emission.radiance) && !(shape.area() > 0)) p.fail("emission", "emitter has zero area");
  // An emitter's power, π·L·area (twice if two-sided), weighs its selection
  // as a light's does (checkLightPowers); computed in double, it must fit a float.
  // Only for an emitter: a large shape that emits nothing was refused under
  // its `emission`, a key never written (0 × an area beyond a float is NaN).
  if (double phi = (emission.twoSided ? 2 : 1) * Pi * double(std::max({emission.radiance.r, emission.radiance.g, emission.radiance.b})) *
                   double(shape.area());
      !isBlack(emission.radiance) && !(phi <= double(std::numeric_limits<float>::max())))
    p.fail("emission", "the emitter's power (π × radiance × area) is beyond a float's range; lower it");
  else if (!isBlack(emission.radiance))
    ctx.lights.push_back({nullptr, p, "emission", phi});
  p.checkUnused();
  shape.materialId = material;
  shape.triangleMaterials = std::move(triangleMaterials);
  if (!shape.isSphere() && !shape.triangleMesh().uvSeam.empty()) {
    bool textured = material >= 0 && scene.material(material).texture();
    for (int m : shape.triangleMaterials) textured |= m >= 0 && scene.material(m).texture();
    if (textured)
      ctx.warnings.push_back(p.file() + ":" + std::to_string(p.line()) + ": " + p.context() + ": " +
                             shape.triangleMesh().uvSeam);
  }
  const Bounds3 box = shape.bounds();
  // The key that put it there: a sphere's center if that alone is too far,
  // else its radius (or its transform); a mesh's transform, else its file.
  std::string placedBy = p.has("transform") ? "transform" : shape.isSphere() ? "radius" : "file";
  if (shape.isSphere() && !(std::max({std::abs(box.center().x), std::abs(box.center().y), std::abs(box.center().z)}) <= kMaxCoordinate))
    placedBy = "center";
  checkCoordinates(p, placedBy, box.lo);
  checkCoordinates(p, placedBy, box.hi);
  scene.addShape(std::move(shape), emission);
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
      map = readExr(full.string());
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

void readCamera(Params& root, Scene& scene, const LoadContext& ctx) {
  int width = 256, height = 256;
  if (auto film = root.getChild("film")) {
    width = film->getInt("width", width);
    height = film->getInt("height", height);
    if (width <= 0) film->fail("width", "must be positive");
    if (height <= 0) film->fail("height", "must be positive");
    checkFilmMemory(*film, width, height);
    film->checkUnused();
  }
  auto cam = root.getChild("camera");
  if (!cam) root.fail("camera", "is required");
  Vec3 pos = cam->requireVec3("position"), target = cam->requireVec3("look_at");
  Vec3 up = cam->getVec3("up", Vec3(0, 1, 0));
  float fov = cam->getFloat("fov", 40);
  std::string axis = cam->getChoice("fov_axis", "y", {"y", "x", "diagonal", "smaller", "larger"});
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
}

SceneFile loadFromNode(const YAML::Node& root, const std::string& path, bool deferWarnings = false) {
  SceneFile out;
  out.path = path;
  out.scene = std::make_unique<Scene>();
  Scene& scene = *out.scene;
  Params p(root, path, "");
  LoadContext ctx;
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
  MitsubaImport imp = importMitsubaXml(path);
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
    out = loadFromNode(root, path, options.deferWarnings);
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
  if (isMitsubaXmlPath(path)) return loadImported(path, overrides, options);
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
  return isMitsubaXmlPath(path) ? importMitsubaXml(path).scene : loadYamlFile(path);
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
