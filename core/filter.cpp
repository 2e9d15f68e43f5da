#include "core/filter.h"
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lb {

namespace {

float sinc(float x) { return std::abs(x) < 1e-5f ? 1.f : std::sin(Pi * x) / (Pi * x); }

// Simpson's rule on [lo, hi] with n (even) panels.
template <class F>
double simpson(F f, double lo, double hi, int n) {
  double h = (hi - lo) / n, sum = f(lo) + f(hi);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * f(lo + i * h);
  return sum * h / 3;
}

}  // namespace

const std::vector<std::string>& PixelFilter::names() {
  static const std::vector<std::string> n = {"box", "tent", "gaussian", "mitchell", "lanczos"};
  return n;
}

PixelFilter::Type PixelFilter::typeNamed(const std::string& name) {
  const auto& n = names();
  return Type(std::find(n.begin(), n.end(), name) - n.begin());
}

PixelFilter::PixelFilter(Type type, float radius, float a, float b) : type_(type), radius_(radius), a_(a), b_(b) {
  if (!(radius > 0 && radius <= MaxRadius)) throw std::invalid_argument("pixel filter radius outside (0, 16]");
  auto f = [&](double x) { return double(evaluate1D(float(x))); };
  integral1_ = float(simpson(f, -radius_, radius_, 4096));
  if (type_ == Type::Box || type_ == Type::Tent) return;  // sampled exactly
  // 64 bins per pixel of radius, on each side; each bin's ∫|f₁| by Simpson.
  int bins = 2 * std::max(8, int(std::ceil(64 * radius_)));
  double width = 2.0 * radius_ / bins, total = 0;
  std::vector<double> mass(static_cast<size_t>(bins), 0.0);
  for (int i = 0; i < bins; ++i) {
    double lo = -radius_ + i * width;
    mass[size_t(i)] = simpson([&](double x) { return std::abs(f(x)); }, lo, lo + width, 16);
    total += mass[size_t(i)];
  }
  binCdf_.assign(size_t(bins) + 1, 0.f);
  binPdf_.resize(size_t(bins));
  double running = 0;
  for (int i = 0; i < bins; ++i) {
    running += mass[size_t(i)];
    binCdf_[size_t(i) + 1] = float(running / total);
    binPdf_[size_t(i)] = float(mass[size_t(i)] / (total * width));
  }
  binCdf_.back() = 1;
}

float PixelFilter::evaluate1D(float x) const {
  x = std::abs(x);
  if (x > radius_) return 0;
  switch (type_) {
    case Type::Box: return 1;
    case Type::Tent: return radius_ - x;
    case Type::Gaussian: {
      float s2 = 2 * a_ * a_;
      return std::max(0.f, std::exp(-x * x / s2) - std::exp(-radius_ * radius_ / s2));
    }
    case Type::Mitchell: {  // Mitchell & Netravali 1988, Eq. 8, on [−2, 2]
      float t = 2 * x / radius_, B = a_, C = b_;
      if (t <= 1) return ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t + (6 - 2 * B)) / 6;
      return ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t + (8 * B + 24 * C)) / 6;
    }
    case Type::Lanczos: return sinc(x) * sinc(x / a_);
  }
  return 0;
}

float PixelFilter::sample1D(float u, float* weight) const {
  *weight = 1;
  if (type_ == Type::Box) return radius_ * (2 * u - 1);
  if (type_ == Type::Tent)  // the inverse of the tent's CDF, each half
    return u < 0.5f ? radius_ * (std::sqrt(2 * u) - 1) : radius_ * (1 - std::sqrt(2 * (1 - u)));
  size_t bins = binPdf_.size();
  size_t i = std::min(bins - 1, size_t(std::upper_bound(binCdf_.begin(), binCdf_.end(), u) - binCdf_.begin()) - 1);
  while (binPdf_[i] == 0 && i + 1 < bins) ++i;  // u on a flat stretch of the CDF
  float within = (u - binCdf_[i]) / (binCdf_[i + 1] - binCdf_[i]);
  float width = 2 * radius_ / float(bins);
  float x = std::clamp(-radius_ + (float(i) + std::clamp(within, 0.f, OneMinusEpsilon)) * width, -radius_, radius_);
  *weight = evaluate1D(x) / (integral1_ * binPdf_[i]);
  return x;
}

float PixelFilter::pdf1D(float x) const {
  if (std::abs(x) > radius_) return 0;
  if (type_ == Type::Box) return 1 / (2 * radius_);
  if (type_ == Type::Tent) return (radius_ - std::abs(x)) / (radius_ * radius_);
  size_t bins = binPdf_.size();
  size_t i = std::min(bins - 1, size_t((x + radius_) / (2 * radius_) * float(bins)));
  return binPdf_[i];
}

PixelFilter::Sample PixelFilter::sample(Vec2 u) const {
  float wx, wy;
  Vec2 offset(sample1D(u.x, &wx), sample1D(u.y, &wy));
  return {offset, wx * wy};
}

}  // namespace lb
