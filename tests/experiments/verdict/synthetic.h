#pragma once
// Synthetic scenes with a known truth for the verdict's tests: a true image
// μ, a reference that is the mean of `chunks` noisy chunks (its per-pixel
// variance of the mean estimated from their spread, as experiments/chunks.h
// does), and configurations x = μ + bias + noise whose true MSE against μ is
// known in closed form: bias² + σ² (Gaussian noise), the same for every pixel.
// `grey`: one noise draw for a pixel's three channels (fully correlated, as
// a path's throughput makes them), else one per channel (independent).
#include <random>
#include "experiments/verdict/verdict.h"

namespace lb::synthetic {

struct Scene {
  Image truth, reference, variance;
  uint64_t chunks = 0;
};

inline Scene makeScene(int w, int h, uint64_t chunks, double chunkSigma, std::mt19937_64& rng, bool grey = false) {
  Scene s;
  s.truth = Image(w, h);
  std::uniform_real_distribution<double> level(0.2, 1.0);
  for (auto& p : s.truth.pixels) p = Color(float(level(rng)), float(level(rng)), float(level(rng)));
  s.chunks = chunks;
  s.reference = Image(w, h), s.variance = Image(w, h);
  std::normal_distribution<double> noise(0, chunkSigma);
  for (size_t i = 0; i < s.truth.pixels.size(); ++i) {
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    for (uint64_t k = 0; k < chunks; ++k) {
      double shared = noise(rng);
      for (int c = 0; c < 3; ++c) {
        double v = s.truth.pixels[i][c] + (grey ? shared : noise(rng));
        sum[c] += v, sum2[c] += v * v;
      }
    }
    for (int c = 0; c < 3; ++c) {
      double mean = sum[c] / double(chunks);
      s.reference.pixels[i][c] = float(mean);
      // Variance of the mean: the sample variance over chunks / chunks.
      s.variance.pixels[i][c] = float((sum2[c] - double(chunks) * mean * mean) / double(chunks - 1) / double(chunks));
    }
  }
  return s;
}

inline Image noisyImage(const Image& truth, double sigma, double bias, std::mt19937_64& rng, bool grey = false) {
  Image x(truth.width, truth.height);
  std::normal_distribution<double> noise(0, sigma);
  for (size_t i = 0; i < x.pixels.size(); ++i) {
    double shared = noise(rng);
    for (int c = 0; c < 3; ++c) x.pixels[i][c] = float(truth.pixels[i][c] + bias + (grey ? shared : noise(rng)));
  }
  return x;
}

struct Config {
  double sigma = 0.1, bias = 0;
  bool grey = false;
};

// Evidence for the verdict: `repeats` images of each configuration, all
// run for one second.
inline SceneEvidence evidence(const Scene& s, const std::vector<Config>& configs, const std::vector<int>& repeats,
                              std::mt19937_64& rng) {
  SceneEvidence e;
  e.reference = s.reference, e.referenceVariance = s.variance, e.referenceChunks = s.chunks;
  for (size_t i = 0; i < configs.size(); ++i) {
    ConfigurationEvidence c;
    c.label = "c" + std::to_string(i);
    for (int r = 0; r < repeats[i]; ++r) {
      c.finals.push_back(noisyImage(s.truth, configs[i].sigma, configs[i].bias, rng, configs[i].grey));
      c.seconds.push_back(1.0);
    }
    e.configurations.push_back(std::move(c));
  }
  return e;
}

inline bool anyDecided(const SceneVerdict& v) {
  for (const auto& p : v.pairs)
    if (p.decided) return true;
  return false;
}

// The binomial allowance of an observed rate: k/n ≤ p + 3 √(p(1 − p)/n).
inline double upperAllowance(double p, int n) { return p + 3 * std::sqrt(p * (1 - p) / n); }

}  // namespace lb::synthetic
