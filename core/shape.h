#pragma once
// Shapes: triangle meshes (rectangles, boxes and mesh files become meshes) and
// exact spheres. A shape knows its area and samples points uniformly by area;
// spheres also sample the cone of directions they subtend (solid angle).
#include <string>
#include <vector>
#include "core/interaction.h"
#include "core/sampling.h"

namespace lb {

struct TriangleMesh {
  std::vector<Vec3> positions;    // world space
  std::vector<Vec3> normals;      // per vertex, world space; empty if none
  std::vector<Vec2> uvs;          // per vertex; empty if none
  std::vector<glm::uvec3> triangles;
  // Per triangle, its group in the file (an OBJ's usemtl), for per-group
  // materials; empty when the file has one group or they could not be matched.
  std::vector<int> triangleGroups;
  std::vector<std::string> groupNames;
  std::string groupsUnmatched;  // why triangleGroups is empty despite several groups, or ""
  std::string uvSeam;           // "file:line: …" where the file's uvs have a seam lightbench merges, or ""
};

struct Sphere {
  Vec3 center;
  float radius;
  bool flipNormals = false;  // normals point inward (for enclosing spheres)
};

struct ShapeSample {
  Vec3 p, pError, n;
  float pdfArea = 0;  // with respect to area
};

class Shape {
 public:
  static Shape mesh(TriangleMesh mesh);
  static Shape sphere(Sphere s);

  bool isSphere() const { return isSphere_; }
  const TriangleMesh& triangleMesh() const { return mesh_; }
  const Sphere& sphereData() const { return sphere_; }
  float area() const { return area_; }
  Bounds3 bounds() const;

  ShapeSample sampleArea(float uPick, Vec2 u) const;
  // Sphere only: solid-angle sampling from `ref` (uniform cone), falling back to
  // area sampling inside the sphere. Returns pdf per solid angle.
  ShapeSample sampleSolidAngle(const Vec3& ref, Vec2 u, float* pdfSolidAngle) const;
  float solidAnglePdf(const Vec3& ref, const Vec3& pOnShape, const Vec3& nOnShape) const;

  // Fills geometric data of a hit on primitive `prim` at barycentrics (u, v).
  void fillInteraction(const Ray& ray, float t, int prim, float u, float v, SurfaceInteraction& si) const;
  // The uv at barycentrics (u, v) of triangle `prim` (what fillInteraction sets).
  Vec2 uvAt(int prim, float u, float v) const;
  // Sets si.dpdu and si.dpdv at a hit fillInteraction made: from the
  // triangle's uvs (pbrt-v4 §6.5.3), its edges where it has none, and the
  // sphere's (φ/2π, θ/π) parametrisation.
  void surfaceTangents(SurfaceInteraction& si) const;

  int materialId = -1;
  std::vector<int> triangleMaterials;  // per triangle (per-group materials), else empty: materialId
  int lightId = -1;

 private:
  bool isSphere_ = false;
  TriangleMesh mesh_;
  Sphere sphere_{};
  ShapeSample sphereSampleAt(const Vec3& unitDirection) const;
  DiscreteDistribution triangleAreas_;
  float area_ = 0;
};

}  // namespace lb
