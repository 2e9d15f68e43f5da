#pragma once
// Russian roulette and splitting driven by what earlier passes learned
// (`path` with `rrs: adrrs | ears`; issue 37):
//
//  * ADRRS, Vorba & Křivánek 2016, "Adjoint-driven Russian roulette and
//    splitting": a weight window around the pixel's estimate. The expected
//    contribution of a vertex's continuation relative to its pixel,
//        x = avg_c( w_c · L̄_c ),   w = β / (P + 0.01),
//    (β the path throughput, L̄ the cached mean radiance a continuation from
//    here brings back, P the pixel estimate) is kept inside [2/(1+s), 2s/(1+s)],
//    s = 5: below it the path is rouletted with q = x / (1/3), above it split
//    into q = x / (5/3).
//  * EARS, Rath, Grittmann, Herholz, Vévoda, Slusallek & Křivánek 2022,
//    "Efficiency-aware Russian roulette and splitting": the factor that
//    maximises the image's efficiency (1 / (variance × cost)),
//        q = sqrt( avg_c( w_c² · M_c / C ) ) · sqrt( C_img / E_img ),
//    M the continuation's second moment (R) or variance (S), C its cost, and
//    C_img, E_img the cost and relative squared error of one camera sample of
//    the whole image. The second moment decides roulette, the variance
//    splitting: q = R if R ≤ 1; else 1 if S < 1; else S.
//  Both are clamped to [0.05, 20] (a zero estimate must not end paths for
//  good), and q becomes n = ⌊q + u⌋ continuations, each weighted 1/q
//  (with the vertex's light samples, rrs_split_light; path_splitting.cpp):
//  E[n]/q = 1, so the estimator is unbiased for any learned state.
//  Where the cache knows too little (and at specular vertices, and in the
//  warm-up passes) classic roulette decides, as `rrs: classic` would; what
//  it teaches the cache is recorded as a learned q = p would be: only the
//  continuations it keeps, per unit of the β/p they carry (its light
//  samples, taken in full, per unit of β) (as the authors
//  record only continuations taken; recording the killed ones as zeros
//  keeps the mean but inflates M by 1/p and cuts C by p, q by 1/p).
//  (The authors' ADRRS leaves a bin whose mean is 0 alone, q = 1; ours
//  applies the window, x = 0, so the clamp's 0.05.)
//
// Facts from the authors' code (iRath96/ears, recursive_path.cpp, octtree.h);
// what we do differently, and why:
//  * There, a split repeats the vertex's light sample with each continuation,
//    and L̄, M and C are those of the whole reflected-radiance estimate;
//    so here, by default. With rrs_split_light false the light samples are
//    drawn once, before, the split covers the BSDF-sampled continuation
//    only (the part our classic roulette decides on), and L̄, M and C are
//    the continuation's. (Which pays depends on the scene: docs/results.md.)
//  * There, an octree refines where samples fall, with 4 × 4 direction bins
//    per leaf; here a uniform grid (`rrs_cells` along the scene's longest
//    side) with the same 4 × 4 bins of the arriving ray's direction, a bin
//    with too few samples falling back to its cell's total.
//  * There, the pixel estimate is the denoised image so far; here it is the
//    3 × 3 box mean of the passes so far (we ship no denoiser on the hot
//    path). The 0.01 in P + 0.01 is theirs; so is leaving a pass's largest
//    errors out of E_img, but they leave out 10 of a pass of many samples per
//    pixel, we 10 per million (at our sizes, one sample per pixel a pass,
//    10 would be a far larger share of the tail).
//  * There, cost is modelled as time per ray; here it is rays (camera, BSDF
//    and shadow alike, as their two equal constants make it).
//  * There, iterations double in length and are combined by inverse-variance
//    weights, and E_img and C_img are the last iteration's; here every pass
//    counts equally in the film (an image weighted by its own variance
//    estimate is biased), the cache learns after every pass, and E_img and
//    C_img are those of the last half of the passes so far.
//
// Determinism: the continuations' sums are kept per thread as 128-bit fixed
// point integers, whose addition is exact and associative, so the cache after
// a pass does not depend on which thread traced which tile; the pixel
// estimates are per pixel. Learning happens between passes only.
// Speed: a path appends each continuation to its thread's log, and the log
// is added to the thread's sums a batch at a time. (Added one by one, the
// sums' scattered 120-byte slots, about 1 MB a thread at 8 cells, cost EARS
// a fifth of its rays per second on the Cornell box: 2 cells against 8,
// factors held at 1.)
#include <algorithm>
#include <memory>
#include <vector>
#include "core/math.h"

namespace lb {

enum class RrsMethod { Classic, Adrrs, Ears };

// The clamp both learned methods apply to their factor.
constexpr float MinSplitFactor = 0.05f;
constexpr float MaxSplitFactor = 20.f;
// The pixel estimate's offset in the relative metric: w = β / (P + 0.01).
constexpr float RelativePixelOffset = 0.01f;

// What the cache knows about one continuation's estimate L (the radiance a
// BSDF-sampled continuation brings back to a vertex, per unit throughput).
struct ContinuationStats {
  Color mean{0.f}, secondMoment{0.f}, variance{0.f};
  float cost = 0;  // rays one continuation traces, on average
};

// ADRRS's window (s = 5) on x = avg_c(w_c L̄_c), before the clamp.
float adrrsFactor(const Color& relativeThroughput, const Color& mean);
// EARS's factor before the clamp; `imageFactor` = sqrt(C_img / E_img).
float earsFactor(const Color& relativeThroughput, const ContinuationStats& s, float imageFactor);
inline float clampSplitFactor(float q) { return std::min(MaxSplitFactor, std::max(MinSplitFactor, q)); }
// L / β per channel (0 where β is): a continuation's estimate per unit throughput.
inline Color perUnitThroughput(const Color& L, const Color& beta) {
  Color out(0.f);
  for (int c = 0; c < 3; ++c) out[c] = beta[c] > 0 ? L[c] / beta[c] : 0.f;
  return out;
}

// The continuations' statistics over a uniform grid of cells and 4 × 4 bins
// of the arriving direction.
class ContinuationCache {
 public:
  static constexpr int DirectionBins = 16;
  // `cells` along the longest side of `bounds`; a bin is used from
  // `minSamples` recorded continuations on (else its cell's total is).
  ContinuationCache(const Bounds3& bounds, int cells, int minSamples);
  ~ContinuationCache();
  ContinuationCache(ContinuationCache&&) noexcept;
  // Cells × bins: slot() is below this.
  size_t slotCount() const { return stats_.size() / (DirectionBins + 1) * DirectionBins; }

  struct Sums;           // one cell and bin's sums (roulette_splitting.cpp)
  struct ThreadRecords;  // a thread's log of continuations and its sums
  // Continuations a thread logs before it adds them to its sums.
  static constexpr size_t RecordBatch = 4096;
  // The calling thread's records (kept apart until update()).
  ThreadRecords* threadRecords();
  // The cell and bin of point p for a ray arriving along `arriving`.
  size_t slot(const Vec3& p, const Vec3& arriving) const;
  // One continuation from a slot: its estimate L (per unit throughput) and
  // the rays it traced, logged in `records`, the calling thread's.
  void record(ThreadRecords* records, size_t slot, const Color& L, double cost) const;
  // Between passes: the threads' sums join the totals, and lookup() sees them.
  void update();
  // The statistics of a slot, or null where too few continuations were recorded.
  const ContinuationStats* lookup(size_t slot) const;
  // Every continuation recorded up to the last update(), all slots together
  // (for tests): their statistics, and their number in `count`.
  ContinuationStats overall(int64_t* count) const;

 private:
  size_t cell(const Vec3& p) const;
  static int bin(const Vec3& d);
  Bounds3 bounds_;
  int nx_, ny_, nz_;
  float cellSize_;
  int minSamples_;
  std::unique_ptr<struct ThreadSums> threads_;
  std::vector<Sums> totals_;                    // per cell × bin, then per cell (the bins' sum)
  std::vector<ContinuationStats> stats_;        // same layout
  std::vector<uint8_t> known_;                  // enough samples
};

// The image the factors are relative to: per pixel, the mean of the passes
// so far (P, a 3 × 3 box mean), and EARS's image factor from the last half
// of the passes.
class PixelEstimates {
 public:
  PixelEstimates(int width, int height);
  // One camera sample of pixel (x, y) (one per pixel per pass) and the rays it traced.
  void record(int x, int y, const Color& L, double rays);
  // Between passes.
  void update();
  // P, 0.5 before any pass (as EARS).
  Color estimate(int x, int y) const { return estimates_[index(x, y)]; }
  // sqrt(C_img / E_img) of the last half of the passes so far: C_img their
  // rays per sample, E_img their mean relative squared error
  // avg_c(((L − P) / (P + 0.01))²), each pass's largest 10 per million
  // left out; 0 before a pass with error.
  float imageFactor() const { return imageFactor_; }
  // Passes recorded.
  int passes() const { return passes_; }

 private:
  size_t index(int x, int y) const { return size_t(y) * size_t(width_) + size_t(x); }
  int width_, height_, passes_ = 0;
  std::vector<Color> sums_, estimates_;
  std::vector<float> passError_, passCost_;
  float imageFactor_ = 0;
  struct PassSums {
    double error, cost;  // over the pass's kept samples
  };
  std::vector<PassSums> passSums_;
};

// What the path estimator needs for one camera sample (rrs: adrrs | ears):
// the cache it reads and records into, and this sample's pixel.
struct RrsView {
  const ContinuationCache* cache;
  ContinuationCache::ThreadRecords* records;  // the thread's, for record()
  RrsMethod method;
  bool learned;          // warm-up over: the learned factors (before: classic roulette, still recording)
  Color relativeScale;   // 1 / (P + 0.01) for this sample's pixel
  float imageFactor;     // EARS: sqrt(C_img / E_img)
  void record(size_t slot, const Color& L, double cost) const { cache->record(records, slot, L, cost); }
};

// What an integrator that renders one camera sample per pixel per pass
// (`path`, `guided`) keeps for rrs: adrrs | ears: the cache and the pixel
// estimates, both learning after every pass.
class RrsLearning {
 public:
  RrsLearning(RrsMethod method, int warmupPasses, const Bounds3& bounds, int cells, int minSamples, int width,
              int height)
      : method_(method), warmup_(warmupPasses), cache_(bounds, cells, minSamples), pixels_(width, height) {}
  // The view for one camera sample of pixel (x, y), on the calling thread.
  RrsView view(int x, int y) {
    return {&cache_, cache_.threadRecords(), method_, pixels_.passes() >= warmup_,
            Color(1.f) / (pixels_.estimate(x, y) + Color(RelativePixelOffset)), pixels_.imageFactor()};
  }
  // That sample's estimate and the rays it traced.
  void recordPixel(int x, int y, const Color& L, double rays) { pixels_.record(x, y, L, rays); }
  // Between passes.
  void endPass() {
    cache_.update();
    pixels_.update();
  }
  const ContinuationCache& cache() const { return cache_; }
  const PixelEstimates& pixels() const { return pixels_; }

 private:
  RrsMethod method_;
  int warmup_;
  ContinuationCache cache_;
  PixelEstimates pixels_;
};

}  // namespace lb
