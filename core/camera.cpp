#include "core/camera.h"

namespace lb {

Camera::Camera(Vec3 position, Vec3 lookAt, Vec3 up, float fovYDegrees, int width, int height)
    : position_(position), width_(width), height_(height), fullWidth_(width), fullHeight_(height) {
  forward_ = glm::normalize(lookAt - position);
  right_ = glm::normalize(glm::cross(forward_, up));
  up_ = glm::cross(right_, forward_);
  tanHalfY_ = std::tan(glm::radians(fovYDegrees) / 2);
  tanHalfX_ = tanHalfY_ * float(width) / float(height);
  planeArea_ = 4 * tanHalfX_ * tanHalfY_;
}

void Camera::crop(int x0, int y0, int x1, int y1) {
  offsetX_ += x0, offsetY_ += y0;
  width_ = x1 - x0, height_ = y1 - y0;
  planeArea_ = 4 * tanHalfX_ * tanHalfY_ * float(width_) * float(height_) / (float(fullWidth_) * float(fullHeight_));
}

Ray Camera::generateRay(Vec2 raster) const {
  float x = (2 * (raster.x + float(offsetX_)) / float(fullWidth_) - 1) * tanHalfX_;
  float y = (1 - 2 * (raster.y + float(offsetY_)) / float(fullHeight_)) * tanHalfY_;
  return {position_, glm::normalize(x * right_ + y * up_ + forward_), Infinity};
}

std::optional<Vec2> Camera::rasterOf(const Vec3& dir) const {
  float cos = glm::dot(dir, forward_);
  if (cos <= 0) return std::nullopt;
  float x = glm::dot(dir, right_) / cos, y = glm::dot(dir, up_) / cos;
  Vec2 raster((x / tanHalfX_ + 1) / 2 * float(fullWidth_) - float(offsetX_),
              (1 - y / tanHalfY_) / 2 * float(fullHeight_) - float(offsetY_));
  float m = filter_.margin();
  if (raster.x < -m || raster.x >= float(width_) + m || raster.y < -m || raster.y >= float(height_) + m)
    return std::nullopt;
  return raster;
}

float Camera::importance(const Vec3& dir) const {
  if (!rasterOf(dir)) return 0;
  float cos = glm::dot(dir, forward_);
  return 1 / (planeArea_ * cos * cos * cos * cos);
}

void Camera::pdfWe(const Vec3& dir, float* pdfPos, float* pdfDir) const {
  *pdfPos = 1;  // pinhole: delta position
  float cos = glm::dot(dir, forward_);
  *pdfDir = rasterOf(dir) ? 1 / (planeArea_ * cos * cos * cos) : 0.f;
}

std::optional<CameraConnection> Camera::connect(const Vec3& p) const {
  Vec3 toCamera = position_ - p;
  float dist2 = glm::dot(toCamera, toCamera);
  if (dist2 == 0) return std::nullopt;
  float dist = std::sqrt(dist2);
  Vec3 wi = toCamera / dist;
  auto raster = rasterOf(-wi);
  if (!raster) return std::nullopt;
  float cos = glm::dot(-wi, forward_);
  return CameraConnection{wi, dist, importance(-wi), dist2 / cos, *raster, position_};
}

}  // namespace lb
