#pragma once
// What the `guided` integrator learns from, and the interface of the two
// learned structures it can use (q_learning.h, sd_tree.h).
//
// Learning never happens while a pass renders: the paths of a pass write
// GuideVertex records into per-tile lists, and learn() applies them after the
// pass, tile by tile in a fixed order. So the distribution a pass samples is
// fixed during the pass and depends only on earlier passes (with the
// independent sampler, on random numbers independent of this pass's), which
// keeps each pass's estimate unbiased, and the image the same for a seed
// whatever the thread count.
#include <memory>
#include <string>
#include <vector>
#include "core/image.h"
#include "integrators/path_estimator/direction_guide.h"

namespace lb::guiding {

// Which way a surface faces: the dominant axis of its geometric normal,
// turned toward the side the path arrived from, and that axis's sign (six
// classes). Both methods keep one distribution per class in each cell or
// leaf, so the two faces of a thin wall — which no cell of a useful size
// separates — do not share one: light on one side of the wall is not sought
// from the other. (An extension of both papers, whose structures are purely
// spatial; on the door scene a leaf straddling the wall between the rooms
// otherwise sends main-room paths into the wall toward the next room's lamp.)
constexpr int OrientationClasses = 6;
inline int orientationClass(const SurfaceInteraction& si) {
  Vec3 n = glm::dot(si.ng, si.wo) >= 0 ? si.ng : -si.ng;
  Vec3 a = glm::abs(n);
  int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return 2 * axis + (n[axis] < 0);
}

// One vertex a camera path scattered from (delta scattering is not recorded).
struct GuideVertex {
  Vec3 p;               // where
  int orientation = 0;  // orientationClass of the surface there
  Vec3 wi;              // the direction sampled there, in world space
  float pdf = 0;        // its density under the mixture that drew it
  Color beta{1.f};      // path throughput after scattering at p
  Color incident{0.f};  // radiance the rest of the path brought back along wi (its contributions / β)
  float emitted = 0;    // luminance of the emission L_e(y, −wi) at the point y that wi reached,
                        // times its MIS weight against the light samples at p (guided.cpp)
  float scattered = 0;  // at y: Q-learning's ∫ f cos Q (q_learning.h); 0 where y was not shaded
};
using TileRecords = std::vector<std::vector<GuideVertex>>;

class GuidingMethod {
 public:
  virtual ~GuidingMethod() = default;
  // A per-thread view of the learned distribution (direction_guide.h).
  virtual std::unique_ptr<DirectionGuide> makeGuide(float bsdfFraction) const = 0;
  // For bootstrapping methods (Q-learning): the light y scatters toward the
  // vertex before it (along y.wo), from what is learned at y.
  virtual float scatteredValue(const SurfaceInteraction& /*y*/, const BSDF& /*bsdf*/) const { return 0; }
  // Learns from one pass's records, in tile order.
  virtual void learn(const TileRecords& records) = 0;
  // Lines for the render's summary (tree or grid statistics).
  virtual std::vector<std::string> statistics() const = 0;
  // The learned density over directions at p, as an image of the square of
  // sphere_map.h (2·height × height pixels: φ across, cos θ down).
  virtual Image densityImage(const Vec3& p, int orientation, int height) const = 0;
};

}  // namespace lb::guiding
