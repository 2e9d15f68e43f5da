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
  void addShape(Shape shape, Emission emission = {});
  void addLight(std::unique_ptr<Light> light) { lights_.push_back(std::move(light)); }
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
