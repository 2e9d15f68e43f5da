#include "core/scene.h"
#include <xmmintrin.h>
#include <pmmintrin.h>
#include <chrono>
#include <stdexcept>
#include "core/lights/area_light.h"
#include "core/textures/surface_maps.h"

namespace lb {

void enableFlushToZero() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

namespace {

// Exact spheres as Embree user geometry. The quadratic is solved in double
// precision with the numerically stable form of pbrt-v4 §6.8.4, so tiny spheres
// far from the origin and huge ones near it intersect alike.
bool intersectSphere(const Sphere& s, const Vec3d& o, const Vec3d& d, double tNear, double tFar, double* tHit) {
  Vec3d c(s.center), oc = o - c;
  double r = s.radius;
  double a = glm::dot(d, d), b = 2 * glm::dot(d, oc), cc = glm::dot(oc, oc) - r * r;
  Vec3d v = oc - (b / (2 * a)) * d;
  double len = glm::length(v);
  double discrim = 4 * a * (r + len) * (r - len);
  if (discrim < 0) return false;
  double root = std::sqrt(discrim);
  double q = b < 0 ? -0.5 * (b - root) : -0.5 * (b + root);
  double t0 = q / a, t1 = cc / q;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > tNear && t0 <= tFar) return *tHit = t0, true;
  if (t1 > tNear && t1 <= tFar) return *tHit = t1, true;
  return false;
}

void sphereBounds(const RTCBoundsFunctionArguments* args) {
  const Sphere& s = *static_cast<const Sphere*>(args->geometryUserPtr);
  // Pad by a relative ulp so the float box contains the exact sphere.
  Vec3 lo = s.center - Vec3(s.radius), hi = s.center + Vec3(s.radius);
  Vec3 pad = gamma(3) * (glm::abs(s.center) + Vec3(s.radius));
  args->bounds_o->lower_x = lo.x - pad.x, args->bounds_o->lower_y = lo.y - pad.y, args->bounds_o->lower_z = lo.z - pad.z;
  args->bounds_o->upper_x = hi.x + pad.x, args->bounds_o->upper_y = hi.y + pad.y, args->bounds_o->upper_z = hi.z + pad.z;
}

template <bool Occlusion>
void sphereQuery(const Sphere& s, RTCRayN* rays, RTCHitN* hits, unsigned N, const int* valid, unsigned geomID,
                 unsigned primID, unsigned instID) {
  for (unsigned i = 0; i < N; ++i) {
    if (!valid[i]) continue;
    Vec3d o(RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i));
    Vec3d d(RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i));
    float& tfar = RTCRayN_tfar(rays, N, i);
    double t;
    if (!intersectSphere(s, o, d, RTCRayN_tnear(rays, N, i), tfar, &t)) continue;
    if (Occlusion) {
      tfar = -Infinity;
      continue;
    }
    tfar = float(t);
    Vec3d n = o + t * d - Vec3d(s.center);
    RTCHitN_Ng_x(hits, N, i) = float(n.x), RTCHitN_Ng_y(hits, N, i) = float(n.y), RTCHitN_Ng_z(hits, N, i) = float(n.z);
    RTCHitN_u(hits, N, i) = 0, RTCHitN_v(hits, N, i) = 0;
    RTCHitN_primID(hits, N, i) = primID;
    RTCHitN_geomID(hits, N, i) = geomID;
    RTCHitN_instID(hits, N, i, 0) = instID;
  }
}

void sphereIntersect(const RTCIntersectFunctionNArguments* args) {
  sphereQuery<false>(*static_cast<const Sphere*>(args->geometryUserPtr), RTCRayHitN_RayN(args->rayhit, args->N),
                     RTCRayHitN_HitN(args->rayhit, args->N), args->N, args->valid, args->geomID, args->primID,
                     args->context->instID[0]);
}

void sphereOccluded(const RTCOccludedFunctionNArguments* args) {
  sphereQuery<true>(*static_cast<const Sphere*>(args->geometryUserPtr), args->ray, nullptr, args->N, args->valid,
                    args->geomID, args->primID, 0);
}

}  // namespace

// Embree's intersection and occlusion filter on a mesh whose material (or one
// of its per-triangle materials) has an opacity: a candidate hit the mask lets
// through is rejected, and Embree goes on to the next one
// (core/textures/surface_maps.h).
void Scene::opacityFilter(const RTCFilterFunctionNArguments* args) {
  const auto& masked = *static_cast<const MaskedShape*>(args->geometryUserPtr);
  const Shape& shape = *masked.shape;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    int material = shape.triangleMaterials.empty() ? shape.materialId : shape.triangleMaterials[prim];
    if (material < 0) continue;
    const Texture* opacity = masked.scene->materials_[size_t(material)]->surfaceMaps().opacity.get();
    if (!opacity) continue;
    Vec2 uv = shape.uvAt(int(prim), RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
    RTCRayN* ray = args->ray;
    Vec3 o(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i), RTCRayN_org_z(ray, args->N, i));
    Vec3 d(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i), RTCRayN_dir_z(ray, args->N, i));
    if (passesThrough(opacityOf(opacity->eval(uv)), o, d, RTCHitN_geomID(args->hit, args->N, i), prim))
      args->valid[i] = 0;
  }
}

Scene::Scene() {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("cannot create an Embree device");
  rtcScene_ = rtcNewScene(device_);
}

Scene::~Scene() {
  if (rtcScene_) rtcReleaseScene(rtcScene_);
  for (auto& object : objects_)
    if (object->rtc) rtcReleaseScene(object->rtc);
  if (device_) rtcReleaseDevice(device_);
}

void Scene::addShape(Shape shape, Emission emission) {
  shapes_.push_back(std::move(shape));
  emissions_.push_back(emission);
}

bool Scene::hasOpacity(const Shape& shape) const {
  auto masked = [&](int m) { return m >= 0 && materials_[size_t(m)]->surfaceMaps().opacity; };
  if (masked(shape.materialId)) return true;
  for (int m : shape.triangleMaterials)
    if (masked(m)) return true;
  return false;
}

RTCGeometry Scene::newGeometry(Shape& shape) {
  RTCGeometry g;
  if (shape.isSphere()) {
    g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, 1);
    rtcSetGeometryUserData(g, const_cast<Sphere*>(&shape.sphereData()));
    rtcSetGeometryBoundsFunction(g, sphereBounds, nullptr);
    rtcSetGeometryIntersectFunction(g, sphereIntersect);
    rtcSetGeometryOccludedFunction(g, sphereOccluded);
  } else {
    const TriangleMesh& m = shape.triangleMesh();
    g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.positions.size()));
    for (size_t i = 0; i < m.positions.size(); ++i)
      v[3 * i] = m.positions[i].x, v[3 * i + 1] = m.positions[i].y, v[3 * i + 2] = m.positions[i].z;
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangles.size()));
    for (size_t i = 0; i < m.triangles.size(); ++i)
      idx[3 * i] = m.triangles[i].x, idx[3 * i + 1] = m.triangles[i].y, idx[3 * i + 2] = m.triangles[i].z;
  }
  if (hasOpacity(shape)) {
    if (shape.isSphere()) throw std::runtime_error("opacity is supported on meshes only, not on spheres");
    rtcSetGeometryUserData(g, &maskedShapes_.emplace_back(MaskedShape{&shape, this}));
    rtcSetGeometryIntersectFilterFunction(g, opacityFilter);
    rtcSetGeometryOccludedFilterFunction(g, opacityFilter);
  }
  rtcCommitGeometry(g);
  return g;
}

namespace {

void commitForTracing(RTCScene scene) {
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  // Watertight traversal: without it, rays aimed exactly at a vertex shared by
  // several triangles can slip through a closed mesh (tests/core/geometry_extremes_test.cpp).
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcCommitScene(scene);
}

Vec3 transformPoint(const Mat4& m, const Vec3& p) { return Vec3(m * glm::vec4(p, 1.f)); }

}  // namespace

void Scene::addInstance(int object, const Mat4& objectToWorld) {
  Instance inst;
  inst.object = object;
  inst.toWorld = objectToWorld;
  inst.toObject = glm::inverse(objectToWorld);
  inst.normalToWorld = glm::transpose(glm::inverse(Mat3(objectToWorld)));
  inst.mirrors = glm::determinant(Mat3(objectToWorld)) < 0;
  instances_.push_back(inst);
}

Bounds3 Scene::objectBounds(int object) const {
  Bounds3 b;
  for (const Shape& s : objects_[size_t(object)]->shapes) b.extend(s.bounds());
  return b;
}

void Scene::build(LightSelection selection) {
  auto start = std::chrono::steady_clock::now();
  for (size_t id = 0; id < shapes_.size(); ++id) {
    Shape& shape = shapes_[id];
    bounds_.extend(shape.bounds());
    RTCGeometry g = newGeometry(shape);
    rtcAttachGeometryByID(rtcScene_, g, unsigned(id));
    rtcReleaseGeometry(g);

    if (!isBlack(emissions_[id].radiance)) {
      shape.lightId = int(lights_.size());
      lights_.push_back(std::make_unique<AreaLight>(&shape, emissions_[id].radiance, emissions_[id].twoSided));
    }
  }
  for (auto& object : objects_) {
    object->rtc = rtcNewScene(device_);
    for (size_t id = 0; id < object->shapes.size(); ++id) {
      RTCGeometry g = newGeometry(object->shapes[id]);
      rtcAttachGeometryByID(object->rtc, g, unsigned(id));
      rtcReleaseGeometry(g);
    }
    commitForTracing(object->rtc);
  }
  // Instances take the geometry IDs after the shapes'; their shapes' ids
  // (SurfaceInteraction::shapeId) follow the scene's own shapes.
  int nextShapeId = int(shapes_.size());
  for (size_t i = 0; i < instances_.size(); ++i) {
    Instance& inst = instances_[i];
    inst.firstShapeId = nextShapeId;
    nextShapeId += int(objects_[size_t(inst.object)]->shapes.size());
    Bounds3 local = objectBounds(inst.object);
    if (!local.empty())
      for (int corner = 0; corner < 8; ++corner)
        bounds_.extend(transformPoint(inst.toWorld, Vec3(corner & 1 ? local.hi.x : local.lo.x,
                                                         corner & 2 ? local.hi.y : local.lo.y,
                                                         corner & 4 ? local.hi.z : local.lo.z)));
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, objects_[size_t(inst.object)]->rtc);
    rtcSetGeometryTimeStepCount(g, 1);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &inst.toWorld[0][0]);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(rtcScene_, g, unsigned(shapes_.size() + i));
    rtcReleaseGeometry(g);
  }
  commitForTracing(rtcScene_);
  if (bounds_.empty()) bounds_.extend(camera.position());
  infiniteLights_.clear();
  for (size_t i = 0; i < lights_.size(); ++i) {
    lights_[i]->index = int(i);
    lights_[i]->preprocess(bounds_);
    if (lights_[i]->isInfinite() && !lights_[i]->isDelta()) infiniteLights_.push_back(lights_[i].get());
  }
  lightSampler_ = LightSampler(lights_, selection);
  built_ = true;
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Points move by the transform, normals by its inverse transpose and
// tangents as vectors. A triangle's geometric normal follows its winding
// (core/shape.cpp), which a mirroring transform reverses: the instance's
// faces turn over as the same mesh flattened into the world would (where the
// mesh has vertex normals, those decide, as they do there). The point's
// error bound grows by the transform's own rounding: pbrt-v4 §6.8.6, the
// transform of a point that already carries an error.
void Scene::Instance::toWorldSpace(const Shape& shape, const Ray& worldRay, SurfaceInteraction& si) const {
  const Vec3 pObject = si.p, errObject = si.pError;
  si.p = transformPoint(toWorld, pObject);
  for (int row = 0; row < 3; ++row) {
    float withError = 0, rounding = std::abs(toWorld[3][row]);
    for (int col = 0; col < 3; ++col) {
      withError += std::abs(toWorld[col][row]) * errObject[col];
      rounding += std::abs(toWorld[col][row] * pObject[col]);
    }
    si.pError[row] = (gamma(3) + 1) * withError + gamma(3) * rounding;
  }
  si.ng = glm::normalize(normalToWorld * si.ng);
  Vec3 ns = glm::normalize(normalToWorld * si.shading.n);
  if (!shape.isSphere() && shape.triangleMesh().normals.empty()) {
    if (mirrors) si.ng = -si.ng;
    ns = si.ng;
  } else if (!shape.isSphere() && glm::dot(si.ng, ns) < 0) {
    si.ng = -si.ng;
  }
  si.shading = Frame(ns);
  const Mat3 linear(toWorld);
  si.dpdu = linear * si.dpdu, si.dpdv = linear * si.dpdv;
  si.wo = -worldRay.d;
}

void Scene::toEmbree(const Ray& ray, RTCRay& r) {
  r.org_x = ray.o.x, r.org_y = ray.o.y, r.org_z = ray.o.z;
  r.dir_x = ray.d.x, r.dir_y = ray.d.y, r.dir_z = ray.d.z;
  r.tnear = 0, r.tfar = ray.tMax, r.time = 0, r.mask = ~0u, r.id = 0, r.flags = 0;
}

void Scene::toEmbree(const Ray& ray, RTCRayHit& rh) {
  toEmbree(ray, rh.ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

bool Scene::interaction(const Ray& ray, const RTCRayHit& rh, SurfaceInteraction& si) const {
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  const Instance* instance =
      rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID ? nullptr : &instances_[rh.hit.instID[0] - shapes_.size()];
  const Shape& shape =
      instance ? objects_[size_t(instance->object)]->shapes[rh.hit.geomID] : shapes_[rh.hit.geomID];
  if (instance) {
    // The hit as Embree found it, in the object's space: the same t along the
    // ray moved there (Embree does not renormalise its direction).
    Ray local{transformPoint(instance->toObject, ray.o), Mat3(instance->toObject) * ray.d, ray.tMax};
    shape.fillInteraction(local, rh.ray.tfar, int(rh.hit.primID), rh.hit.u, rh.hit.v, si);
    si.shapeId = instance->firstShapeId + int(rh.hit.geomID);
  } else {
    shape.fillInteraction(ray, rh.ray.tfar, int(rh.hit.primID), rh.hit.u, rh.hit.v, si);
    si.shapeId = int(rh.hit.geomID);
  }
  int material = shape.triangleMaterials.empty() ? shape.materialId : shape.triangleMaterials[size_t(si.primId)];
  si.material = material >= 0 ? materials_[size_t(material)].get() : nullptr;
  si.emitter = !instance && shape.lightId >= 0 ? lights_[size_t(shape.lightId)].get() : nullptr;
  if (si.material && si.material->perturbsShading()) shape.surfaceTangents(si);
  if (instance) instance->toWorldSpace(shape, ray, si);
  if (si.material && si.material->perturbsShading()) applyShadingMaps(*si.material, si);
  return true;
}

bool Scene::intersect(const Ray& ray, SurfaceInteraction& si) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  toEmbree(ray, rh);
  rtcIntersect1(rtcScene_, &context, &rh);
  return interaction(ray, rh, si);
}

bool Scene::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  toEmbree(ray, r);
  rtcOccluded1(rtcScene_, &context, &r);
  return r.tfar < 0;
}

void Scene::intersect1(RTCRayHit& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(rtcScene_, &context, &ray);
}

void Scene::intersect1M(RTCRayHit* rays, size_t n, bool coherent) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcIntersect1M(rtcScene_, &context, rays, unsigned(n), sizeof(RTCRayHit));
}

void Scene::occluded1M(RTCRay* rays, size_t n, bool coherent) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcOccluded1M(rtcScene_, &context, rays, unsigned(n), sizeof(RTCRay));
}

}  // namespace lb
