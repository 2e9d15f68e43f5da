#include "core/mesh_io.h"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace lb {

namespace {
using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
}

size_t transformMesh(TriangleMesh& m, const Mat4& toWorld) {
  glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(toWorld)));
  for (auto& p : m.positions) p = Vec3(toWorld * glm::vec4(p, 1.f));
  for (auto& n : m.normals) n = glm::normalize(normalMatrix * n);
  std::vector<glm::uvec3> kept;
  kept.reserve(m.triangles.size());
  for (const auto& t : m.triangles) {
    Vec3 e = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    if (glm::dot(e, e) > 0 && std::isfinite(glm::dot(e, e))) kept.push_back(t);
  }
  size_t dropped = m.triangles.size() - kept.size();
  m.triangles = std::move(kept);
  return dropped;
}

// OpenMesh 9.0's PLY reader loops forever on a header that never reaches
// "end_header"; refuse such files before handing them over.
void checkPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0)
    throw std::runtime_error("cannot read mesh file (not a PLY file): " + path);
  for (int lines = 0; lines < 10000 && std::getline(in, line); ++lines)
    if (line.rfind("end_header", 0) == 0) return;
  throw std::runtime_error("cannot read mesh file (PLY header has no end_header): " + path);
}

MeshLoadResult loadMesh(const std::string& path, const Mat4& toWorld, bool smoothNormals) {
  if (!std::filesystem::exists(path)) throw std::runtime_error("mesh file not found: " + path);
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = char(std::tolower(c));
  if (ext != ".obj" && ext != ".ply") throw std::runtime_error("unsupported mesh format (use .obj or .ply): " + path);
  if (ext == ".ply") checkPlyHeader(path);
  OMesh om;
  om.request_vertex_normals();
  om.request_vertex_texcoords2D();
  OpenMesh::IO::Options options;
  options += OpenMesh::IO::Options::VertexNormal;
  options += OpenMesh::IO::Options::VertexTexCoord;
  if (!OpenMesh::IO::read_mesh(om, path, options)) throw std::runtime_error("cannot read mesh file: " + path);
  if (om.n_faces() == 0) throw std::runtime_error("mesh has no faces: " + path);
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
      auto t = om.texcoord2D(v);
      m.uvs.emplace_back(t[0], t[1]);
    }
  }
  for (auto f : om.faces()) {
    std::vector<unsigned> idx;
    for (auto v : om.fv_range(f)) idx.push_back(unsigned(v.idx()));
    if (idx.size() == 3) m.triangles.emplace_back(idx[0], idx[1], idx[2]);
  }
  result.degenerateTriangles = transformMesh(m, toWorld);
  return result;
}

}  // namespace lb
