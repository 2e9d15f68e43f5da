#pragma once
// The shared cache of irradiance records and its lookup rules.
//
// Thread safety and determinism: the cache is read-only while a pass runs.
// Records created during a pass go to the list of the image tile that created
// them (one thread runs a tile, in scanline order, so later pixels of the same
// tile see them at once) and join the shared cache after the pass, in tile
// order. Neighbour clamping is applied then, in that same order. Which records
// exist, and every lookup's result, depend only on the seed and the pass, never
// on the thread count or the scheduling.
#include <memory>
#include <vector>
#include "integrators/irradiance_cache/record.h"
#include "integrators/irradiance_cache/record_octree.h"

namespace lb {

struct CacheSettings {
  float a = 0.15f;               // Ward's error threshold
  float minSpacing = 2, maxSpacing = 64;  // bounds of a record's reach a·R
  bool spacingInPixels = true;   // spacing in projected pixels (else world units)
  bool gradients = true;         // extrapolate with the gradients (and limit R by them)
  bool neighbourClamping = true; // Křivánek et al. 2006
};

// The tile-local records of one pass, and the lookups counted with them.
struct LocalRecords {
  std::vector<IrradianceRecord> records;
  uint64_t lookups = 0, hits = 0, nonFinite = 0;
  double lookupSeconds = 0, recordSeconds = 0;
};

class IrradianceCache {
 public:
  IrradianceCache(CacheSettings settings, const Bounds3& sceneBounds);

  // Interpolated irradiance at (p, n) from the shared records and `local`'s;
  // false if no record is valid there (Σ w over records with w > 1/a is zero).
  // Only records computed for `segmentsLeft` count (-1: every record).
  bool interpolate(const Vec3& p, const Vec3& n, const LocalRecords& local, Color& E, int segmentsLeft = -1) const;

  // Clamps a freshly computed record's R: gradient limit R ≤ E/|∇_t E| (when
  // gradients are on), then a·R into [min, max] spacing; `worldPerPixel` is
  // the world size of one pixel at the record (used with pixel spacing).
  void clampRadius(IrradianceRecord& r, float worldPerPixel) const;

  // Adds the records of a pass, in the order given (tile order).
  void merge(std::vector<LocalRecords>& tiles);

  size_t size() const { return records_.size(); }
  const std::vector<IrradianceRecord>& records() const { return records_; }
  const CacheSettings& settings() const { return settings_; }

 private:
  void neighbourClamp(IrradianceRecord& r);
  CacheSettings settings_;
  std::vector<IrradianceRecord> records_;
  RecordOctree octree_;
};

}  // namespace lb
