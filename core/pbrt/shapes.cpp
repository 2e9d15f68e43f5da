// pbrt-v4 shapes, area lights and light sources as lightbench shapes and
// lights (see translator.h; orientation and light normalisation: import.h).
#include <cmath>
#include <filesystem>
#include "core/error.h"
#include "core/math.h"
#include "core/mesh_io.h"
#include "core/pbrt/translator.h"

namespace lb::pbrt {
namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 point(const glm::dmat4& m, glm::dvec3 p) { return glm::dvec3(m * glm::dvec4(p, 1)); }

YAML::Node flowList(const std::vector<double>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (double x : v) n.push_back(x);
  return n;
}

// An inline mesh in object space, oriented as pbrt orients it (import.h):
// each triangle's winding turned to its shading normals' side, then flipped
// where ReverseOrientation and a mirroring CTM differ, since lightbench's
// winding normal turns over under a mirror and pbrt's does not.
struct InlineMesh {
  std::vector<double> p, n, uv;
  std::vector<long> indices;
};

}  // namespace

void Translator::shape(const std::string& type, const ParamSet& ps, const GraphicsState& gs, const Where& at) {
  auto fail = [&](const std::string& message) { throw ConfigError(at.file, at.line, at.column, "", message); };
  const glm::dmat4& ctm = gs.ctm;
  const bool mirrors = glm::determinant(glm::dmat3(ctm)) < 0;
  YAML::Node s(YAML::NodeType::Map);
  double area = 0;  // world-space area, for an area light's `power`
  if (type == "trianglemesh" || type == "bilinearmesh") {
    InlineMesh m;
    m.p = ps.getNumbers("P", {"point3"}, 3);
    if (m.p.empty()) fail(type + " needs \"point3 P\"");
    size_t nv = m.p.size() / 3;
    m.n = ps.getNumbers("N", {"normal3"}, 3);
    m.uv = ps.getNumbers("uv", {"point2"}, 2);
    if (!m.n.empty() && m.n.size() != m.p.size()) ps.fail(*ps.find("N"), "needs one normal per vertex of P");
    if (!m.uv.empty() && m.uv.size() / 2 != nv) ps.fail(*ps.find("uv"), "needs one uv per vertex of P");
    std::vector<long> idx = ps.getInts("indices");
    const size_t corners = type == "trianglemesh" ? 3 : 4;
    if (idx.empty()) {
      if (nv != corners) fail(type + " without \"integer indices\" must have exactly " + std::to_string(corners) + " vertices");
      for (size_t i = 0; i < corners; ++i) idx.push_back(long(i));
    }
    if (idx.size() % corners != 0)
      ps.fail(*ps.find("indices"), "expected a multiple of " + std::to_string(corners) + " indices, got " + std::to_string(idx.size()));
    for (long i : idx)
      if (i < 0 || size_t(i) >= nv) ps.fail(*ps.find("indices"), "index " + std::to_string(i) + " is outside the " + std::to_string(nv) + " vertices");
    if (corners == 4) {
      // A bilinear patch (p00, p10, p01, p11) as two triangles: exact when planar.
      std::vector<long> tri;
      bool planar = true;
      for (size_t q = 0; q < idx.size(); q += 4) {
        auto P = [&](size_t k) { return glm::dvec3(m.p[3 * idx[q + k]], m.p[3 * idx[q + k] + 1], m.p[3 * idx[q + k] + 2]); };
        glm::dvec3 nrm = glm::cross(P(1) - P(0), P(2) - P(0));
        double size = glm::length(P(3) - P(0));
        if (glm::length(nrm) > 0 && std::abs(glm::dot(glm::normalize(nrm), P(3) - P(0))) > 1e-6 * size) planar = false;
        for (size_t k : {0, 1, 3, 0, 3, 2}) tri.push_back(idx[q + k]);
      }
      if (!planar) warn(at, "a non-planar bilinear patch approximated by two triangles");
      idx = tri;
    }
    ps.find("faceIndices");
    if (const Param* p = ps.find("S")) warn(at, "parameter " + p->declaration() + " (tangents) ignored");
    for (size_t t = 0; t < idx.size(); t += 3) {
      auto P = [&](long i) { return glm::dvec3(m.p[3 * i], m.p[3 * i + 1], m.p[3 * i + 2]); };
      glm::dvec3 wind = glm::cross(P(idx[t + 1]) - P(idx[t]), P(idx[t + 2]) - P(idx[t]));
      bool flip = false;
      if (!m.n.empty()) {
        glm::dvec3 ns(0);
        for (int k = 0; k < 3; ++k) ns += glm::dvec3(m.n[3 * idx[t + k]], m.n[3 * idx[t + k] + 1], m.n[3 * idx[t + k] + 2]);
        flip = glm::dot(wind, ns) < 0;
      }
      if (flip != (gs.reverseOrientation != mirrors)) std::swap(idx[t + 1], idx[t + 2]);
      glm::dvec3 a = point(ctm, P(idx[t])), b = point(ctm, P(idx[t + 1])), c = point(ctm, P(idx[t + 2]));
      area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    if (gs.reverseOrientation)
      for (double& x : m.n) x = -x;
    // uvs as pbrt has them (as a PLY's are read): the textures flip v (materials.cpp).
    s["type"] = "triangles";
    s["positions"] = flowList(m.p);
    s["indices"] = flowList(std::vector<double>(idx.begin(), idx.end()));
    if (!m.n.empty()) s["normals"] = flowList(m.n);
    if (!m.uv.empty()) s["uvs"] = flowList(m.uv);
    s["transform"]["matrix"] = rowMajor(ctm);
  } else if (type == "plymesh") {
    std::string file = ps.getString("filename", "");
    if (file.empty()) fail("plymesh needs \"string filename\"");
    if (const Param* p = ps.find("displacement")) warn(at, "parameter " + p->declaration() + " (displacement) not supported; ignored");
    ps.find("edgelength");
    s["type"] = "mesh";
    s["file"] = file;
    s["transform"]["matrix"] = rowMajor(ctm);
    // The file's normals follow ReverseOrientation as its winding does.
    if (gs.reverseOrientation) s["flip_normals"] = true;
    if (gs.areaLight) {
      if (mirrors) warn(at, "an emitting plymesh under a mirroring transform: its emitting side follows the winding, not pbrt's rule");
      std::filesystem::path full = std::filesystem::path(folder_) / file;
      try {
        glm::mat4 m(ctm);
        MeshLoadResult r = loadMesh(full.string(), m, false);
        for (const auto& t : r.mesh.triangles) {
          glm::dvec3 a(r.mesh.positions[t.x]), b(r.mesh.positions[t.y]), c(r.mesh.positions[t.z]);
          area += 0.5 * glm::length(glm::cross(b - a, c - a));
        }
      } catch (const std::runtime_error& e) {
        ps.fail(*ps.find("filename"), e.what());
      }
    }
  } else if (type == "sphere") {
    double r = ps.getFloat("radius", 1);
    if (!(r > 0)) ps.fail(*ps.find("radius"), "must be positive");
    if (ps.getFloat("zmin", -r) > -r || ps.getFloat("zmax", r) < r || ps.getFloat("phimax", 360) < 360)
      warn(at, "a partial sphere (zmin, zmax, phimax) rendered whole");
    glm::dmat3 l(ctm);
    double sx = glm::length(l[0]), sy = glm::length(l[1]), sz = glm::length(l[2]);
    double scale = std::cbrt(std::abs(glm::determinant(l)));
    if (std::abs(sx - sy) > 1e-6 * scale || std::abs(sx - sz) > 1e-6 * scale ||
        std::abs(glm::dot(l[0], l[1])) + std::abs(glm::dot(l[1], l[2])) + std::abs(glm::dot(l[0], l[2])) > 1e-6 * scale * scale)
      warn(at, "a sphere under a non-uniform scale or shear rendered as a sphere of the mean scale");
    s["type"] = "sphere";
    s["center"] = flowVec(point(ctm, glm::dvec3(0)));
    s["radius"] = r * scale;
    if (gs.reverseOrientation != mirrors) s["flip_normals"] = true;
    area = 4 * kPi * r * r;  // pbrt-v4's Sphere::Area: object space, the CTM's scale not included
  } else if (type == "disk") {
    double h = ps.getFloat("height", 0), r = ps.getFloat("radius", 1);
    if (!(r > 0)) ps.fail(*ps.find("radius"), "must be positive");
    if (ps.getFloat("innerradius", 0) > 0 || ps.getFloat("phimax", 360) < 360)
      warn(at, "an annulus or partial disk (innerradius, phimax) rendered whole");
    glm::dmat4 m = ctm * glm::dmat4(glm::dvec4(r, 0, 0, 0), glm::dvec4(0, r, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, 0, h, 1));
    s["type"] = "disk";
    s["transform"]["matrix"] = rowMajor(m);
    // pbrt-v4's Disk intersection flips its normal when ReverseOrientation and a
    // mirroring CTM differ; lightbench's disk winding already turns over under a
    // mirror, so only ReverseOrientation flips here. (pbrt-v4's Disk::Sample
    // flips under ReverseOrientation alone: pbrt disagrees with itself under mirrors.)
    if (gs.reverseOrientation) s["flip_normals"] = true;
    area = kPi * r * r;  // pbrt-v4's Disk::Area: object space
  } else {
    ps.markAllUsed();
    warn(at, "shape '" + type + "' not supported; dropped");
    return;
  }
  if (!gs.material.empty()) s["material"] = gs.material;
  // pbrt-v4's alpha (a float or a float texture) is the shape's; lightbench's
  // opacity is its material's: the shape gets a copy of its material with it.
  if (const Param* p = ps.find("alpha")) {
    YAML::Node opacity;
    std::string key;  // the alpha, as the name of the material's copy
    if (p->type == "float" && p->numbers.size() == 1 && p->numbers[0] < 1) {
      opacity = std::max(0.0, p->numbers[0]);
      key = std::to_string(opacity.as<double>());
    } else if (p->type == "texture" && p->strings.size() == 1 && namedFloatTextures_.count(p->strings[0])) {
      opacity = YAML::Clone(namedFloatTextures_.at(p->strings[0]));
      key = "texture " + p->strings[0];
    } else if (p->type == "texture") {
      warn(at, "alpha: an unknown float texture; the shape is opaque");
    }
    if (!key.empty() && (gs.material.empty() || type == "sphere" || gs.areaLight)) {
      warn(at, std::string("alpha on ") + (gs.material.empty() ? "a shape without a material" : gs.areaLight ? "an area light" : "a sphere") +
                   " not supported; the shape is opaque");
      key.clear();
    }
    if (!key.empty()) {
      // One copy per (material, alpha), shared by every shape that asks for it.
      std::string& name = alphaMaterials_[gs.material + "\n" + key];
      if (name.empty()) {
        YAML::Node m = YAML::Clone(materials_[gs.material]);
        m["opacity"] = opacity;
        interfaceNext_ = interfaceMaterials_.count(gs.material) > 0;
        name = addMaterial(gs.material + "@alpha", m);
      }
      s["material"] = name;
    }
  }
  bool emits = bool(gs.areaLight);
  if (emits && !currentObject_.empty()) {
    warn(at, "area lights in object instances are not supported (pbrt-v4 ignores them too); the shape does not emit");
    emits = false;
  }
  if (emits && interfaceMaterials_.count(gs.material)) {
    // pbrt-v4 (BasicScene::CreateLights) ignores an area light on a surface that is not there.
    warn(at, "an area light on an interface material: pbrt ignores it, so the shape does not emit");
    emits = false;
  }
  if (emits) {
    glm::dvec3 L = gs.areaLight->radiance;
    if (gs.areaLight->power > 0) {
      // pbrt-v4 makes one light per triangle, each scaled to the full power.
      if (size_t(s["indices"] ? s["indices"].size() / 3 : 0) > 1 || type == "plymesh")
        warn(at, "power on a mesh: pbrt-v4 gives each triangle the whole power; lightbench spreads it over the mesh's area");
      // pbrt-v4 DiffuseAreaLight::Create: scale by power / (π · area · sides).
      double sides = gs.areaLight->twoSided ? 2 : 1;
      if (!(area > 0)) throw ConfigError(at.file, at.line, at.column, "power", "an emitter of zero area cannot have a power");
      L *= gs.areaLight->power / (kPi * area * sides);
    }
    s["emission"] = flowVec(L);
    if (gs.areaLight->twoSided) s["two_sided"] = true;
  }
  warnUnused(ps, at);
  if (!currentObject_.empty()) {
    // A shape of an object, in the object's space: placed by each ObjectInstance.
    YAML::Node& list = objects_.at(currentObject_);
    out_.origins.emplace_back("objects." + currentObject_ + "[" + std::to_string(list.size()) + "]", at.mainLine);
    list.push_back(s);
    return;
  }
  out_.origins.emplace_back("shapes[" + std::to_string(shapes_.size()) + "]", at.mainLine);
  shapes_.push_back(s);
}

AreaLight Translator::areaLightSource(const std::string& type, const ParamSet& ps, const Where& at) {
  AreaLight a;
  a.at = at;
  if (type != "diffuse") {
    warn(at, "area light '" + type + "' not supported; read as diffuse");
  }
  auto L = ps.getColor("L", true);
  a.radiance = (L ? L->rgb : glm::dvec3(1)) * ps.getFloat("scale", 1);
  if (L && !L->approximation.empty()) warn(at, L->approximation);
  a.twoSided = ps.getBool("twosided", false);
  a.power = ps.getFloat("power", -1);
  if (ps.has("filename")) {
    ps.getString("filename", "");
    warn(at, "an image-textured area light not supported; it emits L");
  }
  warnUnused(ps, at);
  return a;
}

void Translator::lightSource(const std::string& type, const ParamSet& ps, const Where& at) {
  const glm::dmat4& ctm = gs_.ctm;
  YAML::Node l(YAML::NodeType::Map);
  auto color = [&](const char* name) {
    auto c = ps.getColor(name, true);
    if (c && !c->approximation.empty()) warn(at, c->approximation);
    return (c ? c->rgb : glm::dvec3(1)) * ps.getFloat("scale", 1);
  };
  glm::dvec3 from = ps.getPoint3("from").value_or(glm::dvec3(0)), to = ps.getPoint3("to").value_or(glm::dvec3(0, 0, 1));
  if (type == "point") {
    glm::dvec3 I = color("I");
    // pbrt-v4 PointLight::Create: power / 4π.
    if (double phi = ps.getFloat("power", -1); phi > 0) I *= phi / (4 * kPi);
    l["type"] = "point";
    l["position"] = flowVec(point(ctm, from));
    l["intensity"] = flowVec(I);
  } else if (type == "spot") {
    glm::dvec3 I = color("I");
    double cone = ps.getFloat("coneangle", 30), delta = ps.getFloat("conedeltaangle", 5);
    if (!(cone > 0 && cone < 180)) ps.fail(*ps.find("coneangle"), "must be in (0, 180) degrees");
    double start = std::max(0.0, cone - delta);
    if (double phi = ps.getFloat("power", -1); phi > 0) {
      // pbrt-v4 SpotLight::Create: the smoothstep cone's solid angle.
      double cosEnd = std::cos(glm::radians(cone)), cosStart = std::cos(glm::radians(start));
      double solidAngle = 2 * kPi * ((1 - cosStart) + (cosStart - cosEnd) / 2);
      if (!(solidAngle > 0)) throw ConfigError(at.file, at.line, at.column, "coneangle", "a cone too narrow to give a power to");
      I *= phi / solidAngle;
    }
    if (glm::length(to - from) == 0) throw ConfigError(at.file, at.line, at.column, "", "\"to\" must differ from \"from\"");
    l["type"] = "spot";
    l["position"] = flowVec(point(ctm, from));
    l["look_at"] = flowVec(point(ctm, to));
    l["intensity"] = flowVec(I);
    l["cone_angle"] = cone;
    l["falloff_start"] = start;
  } else if (type == "distant") {
    glm::dvec3 L = color("L");
    if (double e = ps.getFloat("illuminance", -1); e > 0) L *= e;
    glm::dvec3 dir = glm::dmat3(ctm) * (to - from);
    if (!(glm::length(dir) > 0))
      throw ConfigError(at.file, at.line, at.column, "", "the light's direction (to - from) is zero");
    l["type"] = "directional";
    l["direction"] = flowVec(glm::normalize(dir));
    l["irradiance"] = flowVec(L);
  } else if (type == "infinite") {
    if (ps.has("filename")) {
      ps.markAllUsed();
      warn(at, "image environment maps (pbrt-v4's equal-area square images) not supported yet; dropped");
      return;
    }
    glm::dvec3 L = color("L");
    // A constant sky of radiance L gives an upward surface illuminance πL.
    if (double e = ps.getFloat("illuminance", -1); e > 0) L *= e / kPi;
    if (const Param* p = ps.find("portal")) warn(at, "parameter " + p->declaration() + " ignored");
    l["type"] = "environment";
    l["radiance"] = flowVec(L);
  } else {
    ps.markAllUsed();
    warn(at, "light '" + type + "' not supported; dropped");
    return;
  }
  warnUnused(ps, at);
  out_.origins.emplace_back("lights[" + std::to_string(lights_.size()) + "]", at.mainLine);
  lights_.push_back(l);
}

}  // namespace lb::pbrt
