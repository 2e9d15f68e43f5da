#pragma once
// Triangle meshes from OBJ or PLY through OpenMesh, transformed to world space.
// Degenerate (zero-area) triangles are dropped and counted.
#include <string>
#include "core/shape.h"

namespace lb {

struct MeshLoadResult {
  TriangleMesh mesh;
  size_t degenerateTriangles = 0;
};

// Throws std::runtime_error with a one-line reason ("file:line: what") if the
// file is missing, unreadable or malformed (checked before OpenMesh reads it).
MeshLoadResult loadMesh(const std::string& path, const Mat4& toWorld, bool smoothNormals);
// Transforms a mesh in place (normals by the inverse transpose) and drops
// zero-area triangles.
size_t transformMesh(TriangleMesh& mesh, const Mat4& toWorld);

}  // namespace lb
