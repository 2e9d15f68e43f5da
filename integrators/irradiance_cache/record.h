#pragma once
// One irradiance-cache record (Ward, Rubinstein, Clear 1988) with Ward and
// Heckbert's gradients (1992), and how records are computed and interpolated.
//
// A record at x with normal n holds the indirect irradiance E (RGB), the
// harmonic mean distance R of the surfaces seen from x, and per channel the
// rotational and translational gradients. Near x it extrapolates to
//   E_i(x', n') = E + (n × n')·∇_r E + (x' − x)·∇_t E
// and Ward's weight  w = 1 / (|x' − x| / R + sqrt(1 − n·n'))  says how far it
// can be trusted: a lookup uses the records with w > 1/a (error threshold a),
// so a record reaches a distance a·R on its own surface.
#include <array>
#include <functional>
#include "core/frame.h"
#include "core/ray.h"
#include "core/rng.h"

namespace lb {

struct IrradianceRecord {
  Vec3 p, n;                  // position, unit normal (on the side the record was seen from)
  Color E{0.f};               // indirect irradiance
  float R = Infinity;         // harmonic mean distance, after clamping (see IrradianceCache)
  float minR = 0;             // the minimum spacing's floor for R (no clamping goes below it)
  std::array<Vec3, 3> rotationalGradient{Vec3(0.f), Vec3(0.f), Vec3(0.f)};     // per channel (r, g, b)
  std::array<Vec3, 3> translationalGradient{Vec3(0.f), Vec3(0.f), Vec3(0.f)};  // per channel, in the tangent plane
  // The segments its paths were allowed beyond the camera path (path_length.h):
  // a record serves only lookups with the same budget; -1: any (unlimited depth).
  int segmentsLeft = -1;
};

// Ward's weight of record `r` at (p, n); infinite where p = r.p and n = r.n.
float wardWeight(const IrradianceRecord& r, const Vec3& p, const Vec3& n);

// Ward 1988: a record lying in front of p (p is behind its surface, e.g.
// across a concave step) must not be used; small negative offsets relative to
// R are float noise on the same surface.
bool recordInFrontOf(const IrradianceRecord& r, const Vec3& p, const Vec3& n);

// The record's irradiance carried to (p, n) by its gradients.
Color extrapolate(const IrradianceRecord& r, const Vec3& p, const Vec3& n, bool gradients);

// Radiance arriving along a ray and the distance to the surface it came
// from (infinity if the ray escaped).
struct IncidentSample {
  Color L{0.f};
  float distance = Infinity;
};
using IncidentRadiance = std::function<IncidentSample(const Ray& ray, uint64_t direction)>;

struct HemisphereStrata {
  int theta = 16;  // M: strata in sin²θ (equal projected solid angle)
  int phi = 48;    // N: strata in azimuth
};

// Computes a record at p by stratified cosine-weighted sampling of the
// hemisphere around n: one direction per (θ, φ) stratum, jittered by `rng`;
// `spawn(direction)` makes the ray leaving the surface. E = π/(MN) Σ L_jk,
// R = MN / Σ 1/r_jk, and the gradients of Ward & Heckbert 1992 (see record.cpp).
IrradianceRecord computeRecord(const Vec3& p, const Vec3& n, HemisphereStrata strata, Pcg32& rng,
                               const std::function<Ray(const Vec3&)>& spawn, const IncidentRadiance& incident);

}  // namespace lb
