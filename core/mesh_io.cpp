#include "core/mesh_io.h"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <filesystem>
#include <map>
#include <tuple>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include "core/mesh_validation.h"

namespace lb {

namespace {
using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
}

size_t transformMesh(TriangleMesh& m, const Mat4& toWorld) {
  glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(toWorld)));
  for (auto& p : m.positions) p = Vec3(toWorld * glm::vec4(p, 1.f));
  for (auto& n : m.normals) n = glm::normalize(normalMatrix * n);
  std::vector<glm::uvec3> kept;
  std::vector<int> keptGroups;
  kept.reserve(m.triangles.size());
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    // In double: a tiny (huge) triangle's squared area underflows (overflows)
    // a float although its area, which is what the renderer holds, does not.
    glm::dvec3 a(m.positions[t.x]), b(m.positions[t.y]), c(m.positions[t.z]);
    glm::dvec3 e = glm::cross(b - a, c - a);
    const float area = float(0.5 * std::sqrt(glm::dot(e, e)));  // what the renderer holds
    if (!(area > 0 && std::isfinite(area))) continue;
    kept.push_back(t);
    if (!m.triangleGroups.empty()) keptGroups.push_back(m.triangleGroups[i]);
  }
  size_t dropped = m.triangles.size() - kept.size();
  m.triangles = std::move(kept);
  if (!m.triangleGroups.empty()) m.triangleGroups = std::move(keptGroups);
  return dropped;
}

// OpenMesh writes its own warnings to stderr (omerr/omout/omlog); the user
// should see only our one-line error, so its logging is switched off once.
static void silenceOpenMesh() {
  static std::once_flag once;
  std::call_once(once, [] {
    omerr().disable();
    omout().disable();
    omlog().disable();
  });
}

MeshLoadResult loadMesh(const std::string& path, const Mat4& toWorld, bool smoothNormals) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw std::runtime_error("mesh file not found: " + path);
  // A directory, FIFO or device would be read forever or not at all.
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(path + ": not a regular file");
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = char(std::tolower(c));
  if (ext != ".obj" && ext != ".ply") throw std::runtime_error("unsupported mesh format (use .obj or .ply): " + path);
  if (std::filesystem::file_size(path, ec) == 0) throw std::runtime_error(path + ": file is empty");
  if (!std::ifstream(path)) throw std::runtime_error(path + ": cannot open the file (permissions?)");
  // OpenMesh trusts its input (see mesh_validation.h): check the structure first.
  ObjFaceGroups groups;
  if (ext == ".ply") validatePlyFile(path);
  else groups = validateObjFile(path);
  silenceOpenMesh();
  OMesh om;
  om.request_vertex_normals();
  om.request_vertex_texcoords2D();
  OpenMesh::IO::Options options;
  options += OpenMesh::IO::Options::VertexNormal;
  options += OpenMesh::IO::Options::VertexTexCoord;
  if (!OpenMesh::IO::read_mesh(om, path, options)) throw std::runtime_error(path + ": the mesh reader could not read the file");
  if (om.n_faces() == 0) throw std::runtime_error(path + ": no faces (all faces were degenerate or non-manifold)");
  bool hasNormals = options.check(OpenMesh::IO::Options::VertexNormal);
  if (!hasNormals && smoothNormals) {
    om.request_face_normals();
    om.update_normals();
    hasNormals = true;
  }
  bool hasUvs = options.check(OpenMesh::IO::Options::VertexTexCoord);

  MeshLoadResult result;
  TriangleMesh& m = result.mesh;
  for (auto v : om.vertices()) {
    auto p = om.point(v);
    m.positions.emplace_back(p[0], p[1], p[2]);
    if (hasNormals) {
      auto n = om.normal(v);
      m.normals.emplace_back(n[0], n[1], n[2]);
    }
    if (hasUvs) {
      // Texture space has v = 0 at the image's top (core/textures/texture.h);
      // OBJ's vt has it at the bottom, so OBJ files are flipped as Mitsuba
      // does (its obj shape's flip_tex_coords, on by default). PLY is not.
      auto t = om.texcoord2D(v);
      m.uvs.emplace_back(t[0], ext == ".obj" ? 1 - t[1] : t[1]);
    }
  }
  for (auto f : om.faces()) {
    std::vector<unsigned> idx;
    for (auto v : om.fv_range(f)) idx.push_back(unsigned(v.idx()));
    if (idx.size() == 3) m.triangles.emplace_back(idx[0], idx[1], idx[2]);
  }
  // OpenMesh keeps one uv per vertex: at a texture seam (a position used
  // with two vt) one of them is lost. Said where a texture would show it.
  if (groups.seamLine > 0)
    m.uvSeam = path + ":" + std::to_string(groups.seamLine) + ": a vertex used with two different texture coordinates "
               "(a texture seam); lightbench keeps one uv per vertex, so a texture smears across the seam's triangles";
  // Groups by position: OpenMesh adds the faces in file order, an n-gon as
  // n − 2 consecutive triangles. A face it refused (non-manifold, repeated
  // vertices) shifts every later one, so then the groups are not matched.
  // One named group is a group too (every face in it); only unnamed faces are none.
  if (groups.names.size() > 1 || (groups.names.size() == 1 && !groups.names[0].empty())) {
    m.groupNames = groups.names;
    size_t expected = 0;
    for (int n : groups.faceVertices) expected += size_t(n - 2);
    if (expected != m.triangles.size()) {
      m.groupsUnmatched = "OpenMesh kept " + std::to_string(m.triangles.size()) + " of its " + std::to_string(expected) +
                          " triangles (it refuses non-manifold faces and faces with repeated vertices), so its usemtl "
                          "groups cannot be matched to faces";
    } else {
      for (size_t f = 0; f < groups.faceGroup.size(); ++f)
        m.triangleGroups.insert(m.triangleGroups.end(), size_t(groups.faceVertices[f] - 2), groups.faceGroup[f]);
    }
  }
  result.degenerateTriangles = transformMesh(m, toWorld);
  return result;
}

}  // namespace lb
