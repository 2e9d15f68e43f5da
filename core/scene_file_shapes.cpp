// The `shapes:` of a YAML scene: transforms, built-in meshes, mesh files, spheres,
// their materials and emission (scene_file_parts.h).
#include "core/scene_file_parts.h"
#include "core/memory.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include "core/bsdfs/material_factory.h"
#include "core/mesh_io.h"

namespace lb::scene_file {

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

Mat4 readTransform(Params& shape, float worldScale) {
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
  return glm::scale(Mat4(1.f), Vec3(worldScale)) * m;
}

// Computed in double: a float determinant of 1e90 is Inf, of 1e-90 zero,
// and the message would say "not invertible" without saying why.
void checkInvertible(Params& p, const Mat4& toWorld) {
  double det = std::abs(glm::determinant(glm::dmat4(toWorld)));
  if (!(det >= double(std::numeric_limits<float>::min()) && det <= double(std::numeric_limits<float>::max()))) {
    char msg[220];
    std::snprintf(msg, sizeof msg, "scale (times world_scale) changes volumes by a factor of %g, beyond a float's "
                  "range: the transform cannot be inverted in float (keep each axis's scale within about "
                  "[2.3e-13, 6.9e12])", det);
    p.fail("transform", msg);
  }
}

// `type: instance`: an object of `objects:` placed by `transform` (its
// world_scale applies here, not to the object's shapes).
void readInstance(Params& p, Scene& scene, LoadContext& ctx) {
  std::string name = p.requireString("object");
  auto it = ctx.objects.find(name);
  if (it == ctx.objects.end()) {
    std::vector<std::string> names;
    for (auto& kv : ctx.objects) names.push_back(kv.first);
    std::string hint = closestMatch(name, names);
    p.fail("object", "unknown object '" + name + "'" + (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
  }
  Mat4 toWorld = readTransform(p, ctx.worldScale);
  checkInvertible(p, toWorld);
  p.checkUnused();
  Bounds3 local = scene.objectBounds(it->second);
  for (int corner = 0; corner < 8 && !local.empty(); ++corner) {
    Vec3 c(corner & 1 ? local.hi.x : local.lo.x, corner & 2 ? local.hi.y : local.lo.y, corner & 4 ? local.hi.z : local.lo.z);
    checkCoordinates(p, p.has("transform") ? "transform" : "object", Vec3(toWorld * glm::vec4(c, 1.f)));
  }
  scene.addInstance(it->second, toWorld);
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

// `type: triangles`: a mesh written in the scene itself (pbrt's trianglemesh
// imports as one): positions (3 numbers each), indices (3 per triangle) and,
// optionally, normals (one per vertex) and uvs (2 numbers per vertex).
TriangleMesh inlineMesh(Params& p) {
  TriangleMesh m;
  std::vector<float> pos = p.getFloatSequence("positions", 3);
  if (pos.empty()) p.fail("positions", "is required (3 numbers per vertex)");
  size_t n = pos.size() / 3;
  // Indices are read as floats, exact up to 2^24.
  if (n > (size_t(1) << 24)) p.fail("positions", "more than 16,777,216 vertices: write a mesh this large to a PLY file");
  for (size_t i = 0; i < n; ++i) m.positions.emplace_back(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
  std::vector<float> idx = p.getFloatSequence("indices", 3);
  if (idx.empty()) p.fail("indices", "is required (3 vertex indices per triangle)");
  for (float v : idx)
    if (!(v >= 0 && v == std::floor(v) && size_t(v) < n))
      p.fail("indices", "each must be a whole number in [0, " + std::to_string(n - 1) + "] (a vertex of positions)");
  for (size_t t = 0; t < idx.size(); t += 3) m.triangles.emplace_back(unsigned(idx[t]), unsigned(idx[t + 1]), unsigned(idx[t + 2]));
  std::vector<float> nrm = p.getFloatSequence("normals", 3);
  if (!nrm.empty() && nrm.size() != pos.size()) p.fail("normals", "needs one normal (3 numbers) per vertex of positions");
  for (size_t i = 0; i < nrm.size() / 3; ++i) {
    Vec3 v(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
    float size = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    if (!(size > 0)) p.fail("normals", "normal " + std::to_string(i) + " is zero");
    m.normals.push_back(glm::normalize(v / size));
  }
  std::vector<float> uv = p.getFloatSequence("uvs", 2);
  if (!uv.empty() && uv.size() / 2 != n) p.fail("uvs", "needs one uv (2 numbers) per vertex of positions");
  for (size_t i = 0; i < uv.size() / 2; ++i) m.uvs.emplace_back(uv[2 * i], uv[2 * i + 1]);
  return m;
}

void readShape(Params& p, Scene& scene, LoadContext& ctx, int object) {
  std::string type = p.getChoice("type", "", {"mesh", "triangles", "sphere", "rectangle", "box", "disk", "instance"});
  if (type == "instance" && object >= 0) p.fail("type", "an object cannot hold instances (one level of instancing)");
  if (type == "instance") return readInstance(p, scene, ctx);
  if (object >= 0 && p.has("emission"))
    p.fail("emission", "an object's shapes cannot emit: instances do not (as in pbrt-v4); make it a shape of its own");
  const float worldScale = object >= 0 ? 1.f : ctx.worldScale;
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
    s.center = p.getVec3("center", Vec3(0.f)) * worldScale;
    s.radius = p.getFloat("radius", 1.f) * worldScale;
    s.flipNormals = p.getBool("flip_normals", false);
    if (!(s.radius > 0) || !std::isfinite(s.radius)) p.fail("radius", "must be positive");
    shape = Shape::sphere(s);
  } else {
    Mat4 toWorld = readTransform(p, worldScale);
    checkInvertible(p, toWorld);
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
    } else if (type == "triangles") {
      mesh = inlineMesh(p);
      dropped = transformMesh(mesh, toWorld);
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
    if (mesh.triangles.empty() && ctx.imported && isBlack(emission.radiance)) {
      ctx.warnings.push_back(p.file() + ":" + std::to_string(p.line()) + ": " + p.context() +
                             ": every triangle is degenerate (zero area); the shape is dropped");
      p.checkUnused();
      return;
    }
    if (mesh.triangles.empty()) {
      if (!isBlack(emission.radiance)) p.fail("emission", "emitter has zero area (every triangle is degenerate)");
      p.fail(type == "mesh" ? "file" : type == "triangles" ? "positions" : "transform", "shape has zero area (every triangle is degenerate)");
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
  {
    // Opacity is traced through Embree's triangle filter (core/scene.cpp),
    // and an emitter's sampled points do not know of it.
    bool masked = material >= 0 && scene.material(material).surfaceMaps().opacity;
    for (int m : shape.triangleMaterials) masked |= m >= 0 && scene.material(m).surfaceMaps().opacity;
    std::string key = p.has("material") ? "material" : "materials";
    if (masked && shape.isSphere()) p.fail(key, "a material with an opacity is supported on meshes only, not on spheres");
    if (masked && !isBlack(emission.radiance)) p.fail(key, "a material with an opacity cannot be on an emitter");
  }
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
  if (object >= 0) scene.addObjectShape(object, std::move(shape));
  else scene.addShape(std::move(shape), emission);
}

}  // namespace lb::scene_file
