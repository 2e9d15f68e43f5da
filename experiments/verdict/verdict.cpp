#include "experiments/verdict/verdict.h"
#include <algorithm>
#include <numeric>
#include <stdexcept>
#include "experiments/verdict/statistics.h"

namespace lb {

const std::vector<VerdictMetric>& verdictMetrics() {
  static const std::vector<VerdictMetric> table = {
      {"rmse", SquaredError::Mse, false, "mse_corrected"},
      {"relmse", SquaredError::RelMse, false, "relmse_corrected"},
      {"relmse_trimmed", SquaredError::RelMseTrimmed, false, "relmse_trimmed_corrected"},
      {"rmse_crop", SquaredError::Mse, true, "mse_crop_corrected"},
      {"relmse_crop", SquaredError::RelMse, true, "relmse_crop_corrected"},
  };
  return table;
}

std::optional<VerdictMetric> findVerdictMetric(const std::string& name) {
  for (const auto& m : verdictMetrics())
    if (m.name == name) return m;
  return std::nullopt;
}

double displayValue(const std::string& metric, double v) {
  if (metric.rfind("rmse", 0) == 0) return std::isfinite(v) ? std::sqrt(std::max(0.0, v)) : v;
  return v;
}

std::string ConfigurationVerdict::rankGroup() const {
  return rankLow == rankHigh ? std::to_string(rankLow) : std::to_string(rankLow) + "-" + std::to_string(rankHigh);
}

namespace {

// Per value (pixel and channel) of a configuration with two repeats or more:
// the mean over repeats and the sample variance of one repeat.
struct PixelMoments {
  std::vector<double> mean, variance;
};

PixelMoments momentsOf(const std::vector<Image>& finals) {
  PixelMoments m;
  const size_t n = finals[0].pixels.size() * 3, R = finals.size();
  m.mean.assign(n, 0.0), m.variance.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (const Image& f : finals) sum += f.pixels[i / 3][int(i % 3)];
    double mean = sum / double(R), ss = 0;
    for (const Image& f : finals) ss += (f.pixels[i / 3][int(i % 3)] - mean) * (f.pixels[i / 3][int(i % 3)] - mean);
    m.mean[i] = mean, m.variance[i] = ss / double(R - 1);
  }
  return m;
}

bool sameImages(const std::vector<Image>& a, const std::vector<Image>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if (a[k].pixels != b[k].pixels) return false;
  return true;
}

// The bound on a pixel's three correlated channels (Judge::referenceSum).
constexpr double ChannelBound = 3;

// What one scene's judging shares: its evidence, settings, and each
// configuration's pixel moments (computed once).
struct Judge {
  const SceneEvidence& e;
  const VerdictSettings& s;
  std::vector<std::optional<PixelMoments>> moments;
  bool varianceKnown;
  double chunks, chunkDof;

  Judge(const SceneEvidence& evidence, const VerdictSettings& settings) : e(evidence), s(settings) {
    varianceKnown = !e.referenceVariance.pixels.empty();
    // Chunks unknown (0): no small-sample corrections, exact degrees of freedom.
    chunks = e.referenceChunks > 1 ? double(e.referenceChunks) : INFINITY;
    chunkDof = chunks - 1;
    for (const auto& c : e.configurations) {
      if (c.finals.empty()) throw std::invalid_argument("verdict: configuration '" + c.label + "' has no final image");
      moments.push_back(c.finals.size() >= 2 ? std::optional<PixelMoments>(momentsOf(c.finals)) : std::nullopt);
    }
  }

  Crop region(const VerdictMetric& m) const {
    return m.crop && !e.crop.empty() ? e.crop : Crop{0, 0, e.reference.width, e.reference.height};
  }

  // Σ over the metric's values of w² · term(index, r, v) / N², N the number
  // of values, and the degrees of freedom of that sum of per-value variance
  // estimates, each with chunks − 1 (Satterthwaite over the pixels, the
  // negative ones counted as zero): a sum over many pixels is known far
  // better than one pixel's, unless a few pixels hold it.
  //
  // A pixel's three channels are one path's throughput, so their errors are
  // correlated, and the reference's variance of the mean says nothing of
  // their covariance. The variance of a sum of three correlated terms is at
  // most 3 × the sum of their variances (Cauchy–Schwarz: aᵀPa ≤ 3 |a|² for a
  // correlation matrix P), with equality for grey, fully correlated noise:
  // each pixel counts 3 × its channels' sum. Pixels are taken as independent.
  struct ReferenceSum {
    double sum = 0, dof = INFINITY;
  };
  template <typename Term>
  ReferenceSum referenceSum(const VerdictMetric& m, Term term) const {
    Crop c = region(m);
    double sum = 0, positive = 0, squares = 0, n = 0;
    for (int y = c.y0; y < c.y1; ++y)
      for (int x = c.x0; x < c.x1; ++x) {
        double pixel = 0;
        for (int ch = 0; ch < 3; ++ch) {
          size_t i = (size_t(y) * e.reference.width + x) * 3 + ch;
          double r = e.reference.at(x, y)[ch], v = e.referenceVariance.at(x, y)[ch];
          double w = squaredErrorWeight(m.kind, r, s.metric.relEpsilon);
          pixel += w * w * term(i, r, v);
          n += 1;
        }
        double a = ChannelBound * pixel;
        sum += a;
        if (a > 0) positive += a, squares += a * a;
      }
    ReferenceSum out;
    if (n == 0) return out;
    out.sum = sum / (n * n);
    if (squares > 0 && std::isfinite(chunkDof)) out.dof = positive * positive / (squares / chunkDof);
    return out;
  }

  std::vector<SquaredErrorValue> perRepeat(size_t config, const VerdictMetric& m) const {
    std::vector<SquaredErrorValue> out;
    for (const Image& f : e.configurations[config].finals)
      out.push_back(squaredError(f, e.reference, e.referenceVariance, m.kind, s.metric, m.crop ? e.crop : Crop{},
                                 s.tileSize));
    return out;
  }

  Estimate estimate(size_t config, const VerdictMetric& m) const {
    std::vector<SquaredErrorValue> runs = perRepeat(config, m);
    Estimate est;
    est.repeats = int(runs.size());
    const double R = double(runs.size());
    double runsVariance = 0, runsDof = 0, referencePartDof = INFINITY;
    for (const auto& r : runs) est.value += r.corrected / R, est.raw += r.raw / R;
    if (runs.size() >= 2) {
      double ss = 0;
      for (const auto& r : runs) ss += (r.corrected - est.value) * (r.corrected - est.value);
      runsVariance = ss / (R - 1) / R;
      runsDof = R - 1;
      if (varianceKnown) {
        // Unbiased per value for normal chunks (the estimated v and r are
        // then independent): E[v̂²] = v² (c + 1)/(c − 1), and with
        // β̂ = (x̄ − r)² − s²/R − v̂, E[β̂ v̂] = b² v − 2 v²/(c − 1). Summed
        // unclamped (clamping each value would bias it up), then clamped.
        const PixelMoments& pm = *moments[config];
        // c/(c + 1) and 2/(c + 1), written so that c = ∞ gives 1 and 0.
        const double shrink = 1 / (1 + 1 / chunks), extra = 2 / (chunks + 1);
        ReferenceSum correction = referenceSum(m, [&](size_t, double, double v) { return 2 * v * v * shrink; });
        ReferenceSum bias = referenceSum(m, [&](size_t i, double ref, double v) {
          double d = pm.mean[i] - ref;
          return 4 * ((d * d - pm.variance[i] / R - v) * v + extra * v * v);
        });
        est.referenceVariance = correction.sum + std::max(0.0, bias.sum);
        referencePartDof = satterthwaiteDof({correction.sum, std::max(0.0, bias.sum)}, {correction.dof, bias.dof});
      }
    } else {
      // One repeat: batch means over its tiles, which see the reference's noise too.
      BatchMeans b = batchMeans(runs[0].tileSum, runs[0].tileCount);
      runsVariance = b.varianceOfMean, runsDof = b.dof;
    }
    est.runsVariance = runsVariance;
    est.variance = runsVariance + est.referenceVariance;
    est.dof = satterthwaiteDof({runsVariance, est.referenceVariance}, {runsDof, referencePartDof});
    double half = studentTQuantile(1 - s.alpha() / 2, est.dof) * std::sqrt(est.variance);
    est.low = est.value - half, est.high = est.value + half;
    return est;
  }

  // Value of `a` minus value of `b`, tested.
  PairComparison compare(size_t a, size_t b, const VerdictMetric& m, const std::vector<Estimate>& est) const {
    PairComparison p;
    p.a = a, p.b = b;
    p.difference = est[a].value - est[b].value;
    const auto& A = e.configurations[a];
    const auto& B = e.configurations[b];
    double variance = 0, referencePart = 0, partDof = INFINITY;
    if (sameImages(A.finals, B.finals)) {
      // Two labels for one estimator and seeds (the same images): a tie
      // however many repeats, with nothing to estimate a variance from.
      p.dof = INFINITY;
    } else if (A.finals.size() >= 2 && B.finals.size() >= 2) {
      const double Ra = double(A.finals.size()), Rb = double(B.finals.size());
      double va = est[a].runsVariance, vb = est[b].runsVariance;
      if (varianceKnown) {
        const PixelMoments& ma = *moments[a];
        const PixelMoments& mb = *moments[b];
        // (x̄_A − x̄_B)² − s_A²/R_A − s_B²/R_B estimates (b_A − b_B)² without
        // bias and independently of v̂: summed unclamped, then clamped.
        ReferenceSum part = referenceSum(m, [&](size_t i, double, double v) {
          double d = ma.mean[i] - mb.mean[i];
          return 4 * (d * d - ma.variance[i] / Ra - mb.variance[i] / Rb) * v;
        });
        referencePart = std::max(0.0, part.sum);
        partDof = part.dof;
      }
      variance = va + vb + referencePart;
      p.dof = satterthwaiteDof({va, vb, referencePart}, {Ra - 1, Rb - 1, partDof});
    } else if (A.finals.size() == 1 && B.finals.size() == 1) {
      // Paired tiles: what the two images share (the reference's noise, the
      // scene's structure) cancels in each tile's difference.
      SquaredErrorValue ra = perRepeat(a, m)[0], rb = perRepeat(b, m)[0];
      std::vector<double> sums(ra.tileSum.size()), weights(ra.tileSum.size());
      for (size_t t = 0; t < sums.size(); ++t)
        sums[t] = ra.tileSum[t] - rb.tileSum[t], weights[t] = 0.5 * (ra.tileCount[t] + rb.tileCount[t]);
      BatchMeans bm = batchMeans(sums, weights);
      variance = bm.varianceOfMean, p.dof = bm.dof;
      if (std::all_of(sums.begin(), sums.end(), [](double v) { return v == 0; })) variance = 0;
    } else {
      // One repeat against several: the two estimates share the reference,
      // with a covariance of either sign, so Var(A − B) ≤ (σ_A + σ_B)².
      double sa = std::sqrt(est[a].variance), sb = std::sqrt(est[b].variance);
      variance = (sa + sb) * (sa + sb);
      p.dof = satterthwaiteDof({est[a].variance, est[b].variance}, {est[a].dof, est[b].dof});
    }
    p.referenceShare = variance > 0 ? referencePart / variance : 0;
    p.p = twoSidedP(p.difference, std::sqrt(variance), p.dof);
    double half = variance > 0 ? studentTQuantile(1 - s.alpha() / 2, p.dof) * std::sqrt(variance) : 0;
    p.low = p.difference - half, p.high = p.difference + half;
    return p;
  }
};

// The value's interval at level 1 − alpha (for the speed-up's Bonferroni halves).
std::pair<double, double> intervalAt(const Estimate& e, double alpha) {
  double half = studentTQuantile(1 - alpha / 2, e.dof) * std::sqrt(e.variance);
  return {e.value - half, e.value + half};
}

// Where, between (t0, y0) and (t1, y1), a value y is reached: f in [0, 1]
// of the way in log time. Log–log (exact for an error falling as a power of
// time, as unbiased estimators' do) where both values are positive, else linear.
double fractionTo(double y0, double y1, double y) {
  if (y0 > 0 && y1 > 0 && y > 0) return (std::log(y0) - std::log(y)) / (std::log(y0) - std::log(y1));
  return (y0 - y) / (y0 - y1);
}
double between(double y0, double y1, double f) {
  if (y0 > 0 && y1 > 0) return std::exp(std::log(y0) + f * (std::log(y1) - std::log(y0)));
  return y0 + f * (y1 - y0);
}
double logTime(double t0, double t1, double f) { return std::exp(std::log(t0) + f * (std::log(t1) - std::log(t0))); }

// First time a curve (times ascending) is at or below `target`; NaN if never.
double firstCrossing(const std::vector<double>& t, const std::vector<double>& y, double target) {
  for (size_t i = 0; i < t.size(); ++i) {
    if (!(y[i] <= target)) continue;
    if (i == 0 || y[i - 1] == y[i]) return t[i];
    return logTime(t[i - 1], t[i], fractionTo(y[i - 1], y[i], target));
  }
  return NAN;
}

// A curve's value at time x (between snapshots as fractionTo); NaN outside.
double curveAt(const std::vector<std::pair<double, double>>& c, double x) {
  if (c.empty() || x < c.front().first || x > c.back().first) return NAN;
  for (size_t i = 1; i < c.size(); ++i)
    if (x <= c[i].first) {
      double t0 = c[i - 1].first, t1 = c[i].first;
      if (!(t0 > 0) || t1 == t0) return c[i].second;
      return between(c[i - 1].second, c[i].second, (std::log(x) - std::log(t0)) / (std::log(t1) - std::log(t0)));
    }
  return c.back().second;
}

// Time to target from the mean curve over repeats and its interval's edges.
// A curve already below the target at its first snapshot reached it at
// some time up to then: its interval starts at 0.
void timeToTarget(const ConfigurationEvidence& c, double target, double alpha, ConfigurationVerdict& v) {
  if (!std::isfinite(target)) return;
  MeanCurve m = meanCurve(c.curves, alpha);
  if (m.x.empty()) return;
  auto crossing = [&](const std::vector<double>& y) {
    double t = firstCrossing(m.x, y, target);
    return t == m.x.front() ? 0.0 : t;
  };
  v.timeToTarget = firstCrossing(m.x, m.mean, target);
  if (c.curves.size() > 1) v.timeToTargetLow = crossing(m.low), v.timeToTargetHigh = crossing(m.high);
  else if (v.timeToTarget == m.x.front()) v.timeToTargetLow = 0, v.timeToTargetHigh = v.timeToTarget;  // by then
}

}  // namespace

MeanCurve meanCurve(const std::vector<std::vector<std::pair<double, double>>>& curves, double alpha, int points) {
  MeanCurve out;
  if (curves.empty()) return out;
  double lo = 0, hi = INFINITY;
  for (const auto& curve : curves) {
    if (curve.empty()) return out;
    lo = std::max(lo, curve.front().first), hi = std::min(hi, curve.back().first);
  }
  if (!(lo > 0 && hi >= lo)) return out;
  const double R = double(curves.size());
  const double q = R > 1 ? studentTQuantile(1 - alpha / 2, R - 1) : 0;
  for (int i = 0; i < points; ++i) {
    double x = hi > lo ? lo * std::pow(hi / lo, double(i) / (points - 1)) : lo;
    if (i == points - 1) x = hi;  // exactly: rounding must not step past a curve's end
    double sum = 0, ss = 0;
    std::vector<double> ys;
    for (const auto& curve : curves) ys.push_back(curveAt(curve, x));
    for (double y : ys) sum += y;
    double m = sum / R;
    for (double y : ys) ss += (y - m) * (y - m);
    double half = R > 1 ? q * std::sqrt(ss / (R - 1) / R) : 0;
    out.x.push_back(x), out.mean.push_back(m), out.low.push_back(m - half), out.high.push_back(m + half);
    if (!(hi > lo)) break;
  }
  return out;
}

Estimate estimateMetric(const SceneEvidence& e, size_t config, const std::string& metric, const VerdictSettings& s) {
  auto m = findVerdictMetric(metric);
  if (!m) throw std::invalid_argument("verdict: unknown metric '" + metric + "'");
  return Judge(e, s).estimate(config, *m);
}

SceneVerdict judgeScene(const SceneEvidence& e, const VerdictSettings& s) {
  auto metric = findVerdictMetric(s.rankBy);
  if (!metric) throw std::invalid_argument("verdict: unknown metric '" + s.rankBy + "'");
  Judge judge(e, s);
  const size_t K = e.configurations.size();
  SceneVerdict v;
  v.metric = s.rankBy;
  v.referenceVarianceKnown = judge.varianceKnown;
  std::vector<Estimate> est;
  for (size_t i = 0; i < K; ++i) est.push_back(judge.estimate(i, *metric));
  v.order.resize(K);
  std::iota(v.order.begin(), v.order.end(), 0);
  // NaN (a non-finite image) last, never "better".
  auto key = [&](size_t i) { return std::isnan(est[i].value) ? INFINITY : est[i].value; };
  std::stable_sort(v.order.begin(), v.order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  std::vector<size_t> position(K);
  for (size_t k = 0; k < K; ++k) position[v.order[k]] = k;

  // Every pair, the better-ranked first; Holm over all of them.
  for (size_t i = 0; i < K; ++i)
    for (size_t j = i + 1; j < K; ++j) {
      size_t a = v.order[i], b = v.order[j];
      PairComparison p = judge.compare(a, b, *metric, est);
      p.adjacent = j == i + 1;
      v.pairs.push_back(p);
    }
  std::vector<double> ps;
  for (const auto& p : v.pairs) ps.push_back(p.p);
  std::vector<double> adjusted = holmAdjust(ps);
  for (size_t k = 0; k < v.pairs.size(); ++k) {
    v.pairs[k].pAdjusted = adjusted[k];
    v.pairs[k].decided = adjusted[k] < s.alpha();
  }

  v.configurations.resize(K);
  for (size_t i = 0; i < K; ++i) {
    ConfigurationVerdict& c = v.configurations[i];
    c.estimate = est[i];
    int better = 0, worse = 0;
    for (const auto& p : v.pairs)
      if (p.decided) better += p.b == i, worse += p.a == i;
    c.rankLow = 1 + better;
    c.rankHigh = int(K) - worse;
    c.decided = c.rankLow == c.rankHigh;
    const auto& times = e.configurations[i].seconds;
    c.seconds = times.empty() ? 0 : std::accumulate(times.begin(), times.end(), 0.0) / double(times.size());
  }

  // Efficiency, speed-up over the baseline and time to its final value.
  const size_t base = std::min(s.baseline, K - 1);
  v.target = est[base].value;
  auto efficiency = [](double value, double seconds) { return value > 0 && seconds > 0 ? 1 / (value * seconds) : INFINITY; };
  auto [baseLow, baseHigh] = intervalAt(est[base], s.alpha() / 2);
  for (size_t i = 0; i < K; ++i) {
    ConfigurationVerdict& c = v.configurations[i];
    c.efficiency = efficiency(est[i].value, c.seconds);
    c.efficiencyLow = efficiency(est[i].high, c.seconds);
    c.efficiencyHigh = efficiency(est[i].low, c.seconds);
    const double tb = v.configurations[base].seconds;
    if (i == base) {
      c.speedup = c.speedupLow = c.speedupHigh = 1;
    } else {
      auto [low, high] = intervalAt(est[i], s.alpha() / 2);
      // speed-up = (value_base · t_base) / (value_i · t_i), each factor within its interval.
      auto ratio = [&](double num, double den) -> double {
        if (!(num > 0)) return 0.0;
        if (!(den > 0)) return INFINITY;
        return (num * tb) / (den * c.seconds);
      };
      // A baseline whose corrected error is not positive has no speed-up to give.
      c.speedup = est[base].value > 0 ? ratio(est[base].value, est[i].value) : NAN;
      c.speedupLow = ratio(baseLow, high);
      c.speedupHigh = ratio(baseHigh, low);
    }
    if (i == base) c.timeToTarget = c.seconds;  // the baseline reaches its own final value at its end
    else timeToTarget(e.configurations[i], v.target, s.alpha(), c);
  }
  return v;
}

}  // namespace lb
