#include "integrators/path_estimator/roulette_splitting.h"
#include <tbb/enumerable_thread_specific.h>
#include <algorithm>
#include <cmath>

namespace lb {

namespace {
// ADRRS's window (Vorba & Křivánek 2016, §4): s = 5 around the pixel estimate.
constexpr float WindowSize = 5;
constexpr float WindowLow = 2 / (1 + WindowSize);  // 1/3
constexpr float WindowHigh = WindowLow * WindowSize;  // 5/3
// Samples of a pass left out of its image error (the largest; iRath96/ears).
// Per million samples, rounded down: at our image sizes and one sample per
// pixel a pass, their 10 of a pass would be a far larger share.
constexpr double OutliersPerSample = 10e-6;

// 128-bit fixed point, 32 fractional bits: sums that are exact, so their
// order (which thread added what) cannot change them. A continuation's
// estimate is capped at 1e7 (its square at 1e14) for the sums only: the
// factors are heuristics, the image keeps the sample as it is.
using Fixed = __int128;
constexpr double FixedScale = 4294967296.0;
constexpr float CappedEstimate = 1e7f;
// (Through int64 where it fits: the same truncation, without libgcc's slow
// double-to-__int128 call: 2 % of EARS's time on the Cornell box when every value took it.)
Fixed toFixed(double v) {
  const double scaled = v * FixedScale;
  return std::fabs(scaled) < 9.2e18 ? Fixed(int64_t(scaled)) : Fixed(scaled);
}
double fromFixed(Fixed v) { return double(v) / FixedScale; }

float average(const Color& c) { return (c.r + c.g + c.b) / 3; }
}  // namespace

float adrrsFactor(const Color& w, const Color& mean) {
  float x = average(w * mean);
  if (x < WindowLow) return x / WindowLow;
  if (x > WindowHigh) return x / WindowHigh;
  return 1;
}

float earsFactor(const Color& w, const ContinuationStats& s, float imageFactor) {
  if (!(s.cost > 0) || !(imageFactor > 0)) return 1;
  float R = std::sqrt(average(w * w * s.secondMoment / s.cost)) * imageFactor;
  if (!(R > 1)) return R;
  float S = std::sqrt(average(w * w * s.variance / s.cost)) * imageFactor;
  return S < 1 ? 1.f : S;
}

// The sums of a cell and bin: continuations, Σ L, Σ L² (per channel), Σ rays.
struct ContinuationCache::Sums {
  int64_t count = 0;
  Fixed first[3] = {0, 0, 0}, second[3] = {0, 0, 0}, cost = 0;
  void add(const Sums& o) {
    count += o.count;
    cost += o.cost;
    for (int c = 0; c < 3; ++c) first[c] += o.first[c], second[c] += o.second[c];
  }
};

// A thread's continuations not yet in its sums, and its sums.
struct ContinuationCache::ThreadRecords {
  struct Entry {
    uint32_t slot;
    float L[3];
    double cost;
  };
  std::vector<Entry> log;
  std::vector<Sums> sums;
  // The log into the sums (exact, so in any order and batching).
  void fold();
};

struct ThreadSums {
  explicit ThreadSums(size_t n) : records([n] {
    ContinuationCache::ThreadRecords r;
    r.sums.resize(n);
    r.log.reserve(ContinuationCache::RecordBatch);
    return r;
  }) {}
  tbb::enumerable_thread_specific<ContinuationCache::ThreadRecords> records;
};

ContinuationCache::ContinuationCache(const Bounds3& bounds, int cells, int minSamples)
    : bounds_(bounds), minSamples_(minSamples) {
  Vec3 extent = glm::max(bounds.hi - bounds.lo, Vec3(1e-6f));
  cellSize_ = std::max(extent.x, std::max(extent.y, extent.z)) / float(cells);
  nx_ = std::max(1, int(std::ceil(extent.x / cellSize_)));
  ny_ = std::max(1, int(std::ceil(extent.y / cellSize_)));
  nz_ = std::max(1, int(std::ceil(extent.z / cellSize_)));
  size_t cellCount = size_t(nx_) * size_t(ny_) * size_t(nz_);
  size_t bins = cellCount * DirectionBins;
  threads_ = std::make_unique<ThreadSums>(bins);
  totals_.resize(bins + cellCount);
  stats_.resize(bins + cellCount);
  known_.assign(bins + cellCount, 0);
}

ContinuationCache::~ContinuationCache() = default;
ContinuationCache::ContinuationCache(ContinuationCache&&) noexcept = default;

size_t ContinuationCache::cell(const Vec3& p) const {
  Vec3 f = (p - bounds_.lo) / cellSize_;
  int x = std::clamp(int(f.x), 0, nx_ - 1), y = std::clamp(int(f.y), 0, ny_ - 1), z = std::clamp(int(f.z), 0, nz_ - 1);
  return (size_t(z) * size_t(ny_) + size_t(y)) * size_t(nx_) + size_t(x);
}

// 4 × 4 bins of ((cos θ + 1)/2, φ/2π) of the arriving direction (iRath96/ears);
// φ's four bins are its quadrants, read from the signs of x and y.
int ContinuationCache::bin(const Vec3& d) {
  int theta = std::min(3, std::max(0, int((d.z + 1) * 2)));
  int phi = d.y >= 0 ? (d.x >= 0 ? 0 : 1) : (d.x < 0 ? 2 : 3);
  return theta * 4 + phi;
}

size_t ContinuationCache::slot(const Vec3& p, const Vec3& arriving) const {
  return cell(p) * DirectionBins + size_t(bin(arriving));
}

ContinuationCache::ThreadRecords* ContinuationCache::threadRecords() { return &threads_->records.local(); }

void ContinuationCache::record(ThreadRecords* records, size_t slot, const Color& L, double cost) const {
  if (!isFinite(L) || !std::isfinite(cost)) return;
  records->log.push_back({uint32_t(slot), {L[0], L[1], L[2]}, cost});
  if (records->log.size() >= RecordBatch) records->fold();
}

void ContinuationCache::ThreadRecords::fold() {
  for (const Entry& e : log) {
    Sums& s = sums[e.slot];
    ++s.count;
    s.cost += toFixed(e.cost);
    for (int c = 0; c < 3; ++c) {
      double v = std::min(std::max(double(e.L[c]), 0.0), double(CappedEstimate));
      s.first[c] += toFixed(v);
      s.second[c] += toFixed(v * v);
    }
  }
  log.clear();
}

namespace {
ContinuationStats statsOf(const ContinuationCache::Sums& s) {
  ContinuationStats out;
  double n = double(s.count);
  for (int c = 0; c < 3; ++c) {
    double mean = fromFixed(s.first[c]) / n, moment = fromFixed(s.second[c]) / n;
    out.mean[c] = float(mean);
    out.secondMoment[c] = float(moment);
    out.variance[c] = float(std::max(0.0, moment - mean * mean));
  }
  out.cost = float(fromFixed(s.cost) / n);
  return out;
}
}  // namespace

ContinuationStats ContinuationCache::overall(int64_t* count) const {
  Sums all;
  for (size_t i = 0; i < slotCount(); ++i) all.add(totals_[i]);
  *count = all.count;
  return all.count > 0 ? statsOf(all) : ContinuationStats{};
}

void ContinuationCache::update() {
  const size_t cellCount = totals_.size() / (DirectionBins + 1), bins = cellCount * DirectionBins;
  for (auto& local : threads_->records) {
    local.fold();
    for (size_t i = 0; i < bins; ++i) {
      totals_[i].add(local.sums[i]);
      local.sums[i] = Sums{};
    }
  }
  for (size_t cellIndex = 0; cellIndex < cellCount; ++cellIndex) {
    Sums whole;
    for (size_t b = 0; b < DirectionBins; ++b) {
      const Sums& s = totals_[cellIndex * DirectionBins + b];
      whole.add(s);
      known_[cellIndex * DirectionBins + b] = s.count >= minSamples_;
      if (s.count >= minSamples_) stats_[cellIndex * DirectionBins + b] = statsOf(s);
    }
    known_[bins + cellIndex] = whole.count >= minSamples_;
    if (whole.count >= minSamples_) stats_[bins + cellIndex] = statsOf(whole);
  }
}

const ContinuationStats* ContinuationCache::lookup(size_t slot) const {
  if (known_[slot]) return &stats_[slot];
  size_t cellTotal = totals_.size() / (DirectionBins + 1) * DirectionBins + slot / DirectionBins;
  return known_[cellTotal] ? &stats_[cellTotal] : nullptr;
}

PixelEstimates::PixelEstimates(int width, int height)
    : width_(width),
      height_(height),
      sums_(size_t(width) * size_t(height), Color(0.f)),
      estimates_(size_t(width) * size_t(height), Color(0.5f)),
      passError_(size_t(width) * size_t(height), 0.f),
      passCost_(size_t(width) * size_t(height), 0.f) {}

void PixelEstimates::record(int x, int y, const Color& L, double rays) {
  size_t i = index(x, y);
  Color l = isFinite(L) ? L : Color(0.f);
  sums_[i] += l;
  Color norm = estimates_[i] + Color(RelativePixelOffset);
  Color e = (l - estimates_[i]) / norm;
  passError_[i] = average(e * e);
  passCost_[i] = float(rays);
}

void PixelEstimates::update() {
  ++passes_;
  // E_img and C_img of this pass, the largest errors left out.
  std::vector<size_t> order(passError_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  size_t kept = order.size() - size_t(double(order.size()) * OutliersPerSample);
  std::nth_element(order.begin(), order.begin() + long(kept), order.end(), [&](size_t a, size_t b) {
    return passError_[a] < passError_[b] || (passError_[a] == passError_[b] && a < b);
  });
  std::sort(order.begin(), order.begin() + long(kept));  // a fixed summation order
  double error = 0, cost = 0;
  for (size_t k = 0; k < kept; ++k) error += passError_[order[k]], cost += passCost_[order[k]];
  // sqrt(C_img / E_img) over the last half of the passes so far, not the
  // last pass alone: one pass's E_img is heavy-tailed (on the door, from
  // about 10 to 700 between passes) and the factors followed its swings.
  // (The authors take their last iteration's, which doubles in length as
  // the render goes on.)
  passSums_.push_back({error, cost});
  error = cost = 0;
  for (size_t k = passSums_.size() / 2; k < passSums_.size(); ++k)
    error += passSums_[k].error, cost += passSums_[k].cost;
  imageFactor_ = error > 0 ? float(std::sqrt(cost / error)) : 0.f;
  // P: the 3 × 3 box mean of the pixels' means.
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      Color sum(0.f);
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= width_ || yy >= height_) continue;
          sum += sums_[index(xx, yy)];
          ++n;
        }
      estimates_[index(x, y)] = sum / float(n * passes_);
    }
}

}  // namespace lb
