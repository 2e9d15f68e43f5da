#pragma once
// The scene: camera, materials, shapes on Embree 3, and lights. Built by the
// scene loader (scene_loader.h) or by hand in tests, then finalised with build().
#include <embree3/rtcore.h>
#include <yaml-cpp/yaml.h>
#include <deque>
#include <memory>
#include <string>
#include <vector>
#include "core/bsdfs/material.h"
#include "core/camera.h"
#include "core/light_sampler.h"
#include "core/lights/light.h"
#include "core/shape.h"

namespace lb {

// Embree asks for flush-to-zero and denormals-are-zero on every tracing thread.
void enableFlushToZero();

struct Emission {
  Color radiance{0.f};
  bool twoSided = false;
};

class Scene {
 public:
  Scene();
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  int addMaterial(std::unique_ptr<Material> m) {
    materials_.push_back(std::move(m));
    return int(materials_.size()) - 1;
  }
  const Material& material(int id) const { return *materials_[size_t(id)]; }
  size_t materialCount() const { return materials_.size(); }
  void addShape(Shape shape, Emission emission = {});
  void addLight(std::unique_ptr<Light> light) { lights_.push_back(std::move(light)); }
  // Objects and their instances (pbrt-v4's ObjectBegin / ObjectInstance): an
  // object's shapes are kept once, in the object's own space, as an Embree
  // scene of their own, and each instance places the object with an affine
  // transform (an Embree instance geometry), so a thousand copies cost one
  // copy's memory. Instanced shapes do not emit, as in pbrt-v4.
  int addObject() {
    objects_.push_back(std::make_unique<Object>());
    return int(objects_.size()) - 1;
  }
  void addObjectShape(int object, Shape shape) { objects_[size_t(object)]->shapes.push_back(std::move(shape)); }
  void addInstance(int object, const Mat4& objectToWorld);
  // The object's shapes' bounds, in its own space.
  Bounds3 objectBounds(int object) const;
  size_t instanceCount() const { return instances_.size(); }
  // Creates the area lights, commits Embree's BVH, and prepares light sampling.
  void build(LightSelection selection = LightSelection::Power);

  bool intersect(const Ray& ray, SurfaceInteraction& si) const;
  bool occluded(const Ray& ray) const;

  // Streams of rays through Embree's rtcIntersect1M / rtcOccluded1M, for
  // engines that trace many rays at once (integrators/path/wavefront.h). The
  // arrays are the caller's, allocated once and reused; `coherent` tells
  // Embree that neighbouring rays are alike (camera rays). intersect() and
  // occluded() are the same conversions around rtcIntersect1 / rtcOccluded1.
  static void toEmbree(const Ray& ray, RTCRayHit& rh);
  static void toEmbree(const Ray& ray, RTCRay& r);
  void intersect1(RTCRayHit& ray) const;  // rtcIntersect1, no conversion (benchmarks)
  void intersect1M(RTCRayHit* rays, size_t n, bool coherent) const;
  void occluded1M(RTCRay* rays, size_t n, bool coherent) const;
  // The hit a traced `rh` found for `ray`, as intersect() reports it; false if none.
  bool interaction(const Ray& ray, const RTCRayHit& rh, SurfaceInteraction& si) const;

  Camera camera;
  const std::vector<std::unique_ptr<Light>>& lights() const { return lights_; }
  const std::vector<const Light*>& infiniteLights() const { return infiniteLights_; }
  const LightSampler& lightSampler() const { return lightSampler_; }
  const std::vector<Shape>& shapes() const { return shapes_; }
  const Bounds3& bounds() const { return bounds_; }
  double buildSeconds() const { return buildSeconds_; }

 private:
  // A mesh with an opacity, as its Embree filter sees it (stable addresses: a deque).
  struct MaskedShape {
    const Shape* shape;
    const Scene* scene;
  };
  static void opacityFilter(const RTCFilterFunctionNArguments* args);
  bool hasOpacity(const Shape& shape) const;
  std::deque<MaskedShape> maskedShapes_;
  // Embree's geometry for one shape (a triangle mesh, or a sphere as user
  // geometry), with the opacity filter where its material has an opacity.
  RTCGeometry newGeometry(Shape& shape);

  struct Object {
    std::vector<Shape> shapes;  // in the object's space
    RTCScene rtc = nullptr;
  };
  struct Instance {
    int object = 0;
    Mat4 toWorld, toObject;
    Mat3 normalToWorld;  // the inverse transpose of toWorld's linear part
    bool mirrors = false;  // toWorld turns space over (negative determinant)
    int firstShapeId = 0;  // its shapes' SurfaceInteraction::shapeId start here
    // A hit the object's space found, moved to the world's (scene.cpp).
    void toWorldSpace(const Shape& shape, const Ray& worldRay, SurfaceInteraction& si) const;
  };
  std::vector<std::unique_ptr<Object>> objects_;
  std::vector<Instance> instances_;

  RTCDevice device_ = nullptr;
  RTCScene rtcScene_ = nullptr;
  std::vector<std::unique_ptr<Material>> materials_;
  std::vector<Shape> shapes_;
  std::vector<Emission> emissions_;
  std::vector<std::unique_ptr<Light>> lights_;
  std::vector<const Light*> infiniteLights_;
  LightSampler lightSampler_;
  Bounds3 bounds_;
  double buildSeconds_ = 0;
  bool built_ = false;
};

}  // namespace lb
