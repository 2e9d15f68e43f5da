#pragma once
// Pinhole perspective camera. The image plane sits at distance 1 from the
// pinhole; A is its area there. Importance is normalised over the whole image:
// We(ω) = 1/(A cos⁴θ), the direction pdf of a camera ray 1/(A cos³θ), and the
// position is a delta at the pinhole (Veach 1997 §10.3; pbrt-v4 §5.4).
// Raster coordinates run over [0, width) × [0, height), y down.
// A crop window (render --crop) makes the camera's image a sub-rectangle of
// its film: an off-axis window of the same image plane, whose pixels are the
// full film's pixels. Importance is then normalised over the window (its
// area A), so each pixel estimates the same value as in the full render.
// A pixel filter wider than a pixel (core/filter.h) makes each pixel look
// up to margin() = radius − ½ pixel past the image's edge: the camera sees
// that margin too (rasterOf, importance and pdfWe are nonzero there, with
// the same formulas; A stays the image's area), so splats that land in it
// reach the edge pixels as the camera's filtered samples do.
#include <optional>
#include "core/filter.h"
#include "core/ray.h"

namespace lb {

struct CameraConnection {
  Vec3 wi;         // unit direction from the scene point to the pinhole
  float dist;      // distance to the pinhole
  float We;        // importance along -wi
  float pdf;       // solid-angle density at the scene point of choosing the pinhole
  Vec2 raster;
  Vec3 pinhole;
};

class Camera {
 public:
  Camera() = default;
  Camera(Vec3 position, Vec3 lookAt, Vec3 up, float fovYDegrees, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  const Vec3& position() const { return position_; }
  const Vec3& forward() const { return forward_; }

  Ray generateRay(Vec2 raster) const;
  // Camera sample u of pixel (x, y): where it looks, and its filter weight
  // f̂/pdf (core/filter.h). With the one-pixel box: (x, y) + u and weight 1.
  struct FilmSample {
    Vec2 raster;
    float weight;
  };
  FilmSample sampleFilm(int x, int y, Vec2 u) const {
    if (filter_.isPixelBox()) return {Vec2(x, y) + u, 1.f};
    PixelFilter::Sample s = filter_.sample(u);
    return {Vec2(float(x) + 0.5f, float(y) + 0.5f) + s.offset, s.weight};
  }
  const PixelFilter& filter() const { return filter_; }
  void setFilter(const PixelFilter& filter) { filter_ = filter; }
  // Image right becomes −cross(forward, up): a left-handed camera space, as
  // pbrt's (core/pbrt/import.h). The same rays, mirrored left to right.
  void mirrorImage() { right_ = -right_; }
  // Raster position of direction `dir` leaving the pinhole, if on the image
  // or its filter margin.
  std::optional<Vec2> rasterOf(const Vec3& dir) const;
  float importance(const Vec3& dir) const;  // We(ω), 0 off-image
  void pdfWe(const Vec3& dir, float* pdfPos, float* pdfDir) const;
  std::optional<CameraConnection> connect(const Vec3& p) const;
  float imagePlaneArea() const { return planeArea_; }
  // Keeps only pixels [x0, x1) × [y0, y1) of the current image (in its raster
  // coordinates); width() and height() become the window's. The caller checks
  // the window lies inside the image.
  void crop(int x0, int y0, int x1, int y1);

 private:
  Vec3 position_{0.f}, forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
  float tanHalfX_ = 1, tanHalfY_ = 1, planeArea_ = 4;
  int width_ = 1, height_ = 1;
  int fullWidth_ = 1, fullHeight_ = 1;  // the uncropped film
  int offsetX_ = 0, offsetY_ = 0;       // the window's corner in the uncropped film
  PixelFilter filter_;
};

}  // namespace lb
