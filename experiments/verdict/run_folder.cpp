#include "experiments/verdict/run_folder.h"
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include "experiments/experiment.h"  // slug
#include "experiments/run_log.h"

namespace fs = std::filesystem;

namespace lb {

namespace {

nlohmann::json readMeta(const std::string& runDir) {
  fs::path path = fs::path(runDir) / "meta.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": not found (a verdict needs the run's meta.json)");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) throw std::runtime_error(path.string() + ": not JSON");
  if (!j.contains("verdict") || !j["verdict"].is_object())
    throw std::runtime_error(path.string() + ": has no 'verdict' settings (a run started before verdicts existed: "
                             "run it again)");
  return j;
}

std::string imagePath(const std::string& runDir, const std::string& scene, const std::string& label, int repeat) {
  std::string stem = (fs::path(runDir) / (scene + "__" + slug(label))).string();
  return repeat == 0 ? stem + ".exr" : stem + "__repeat" + std::to_string(repeat) + ".exr";
}

// log.csv's runs of one scene: label -> repeat -> the final time and, per
// logged column, its snapshots as (time, value) and (spp, value).
using Curve = std::vector<std::pair<double, double>>;
struct LoggedRun {
  double seconds = 0;
  std::map<std::string, Curve> byTime, bySpp;
  bool finished = false;
};
using LoggedRuns = std::map<std::string, std::map<int, LoggedRun>>;

LoggedRuns readLoggedRuns(const std::string& runDir, const std::string& scene) {
  LoggedRuns out;
  std::ifstream in(fs::path(runDir) / "log.csv");
  std::string line;
  std::vector<std::string> header, f;
  if (!std::getline(in, line)) return out;
  parseCsvLine(line, header);
  auto at = [&](const std::string& name) {
    auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : int(it - header.begin());
  };
  const int cScene = at("scene"), cLabel = at("label"), cRepeat = at("repeat"), cTime = at("time_s"),
            cSpp = at("spp"), cFinal = at("final");
  if (cScene < 0 || cLabel < 0 || cRepeat < 0 || cTime < 0 || cSpp < 0 || cFinal < 0) return out;
  std::vector<std::pair<std::string, int>> columns;
  for (const auto& m : verdictMetrics())
    if (at(m.correctedColumn) >= 0) columns.emplace_back(m.correctedColumn, at(m.correctedColumn));
  while (std::getline(in, line)) {
    if (!parseCsvLine(line, f) || f.size() != header.size() || f[size_t(cScene)] != scene) continue;
    try {
      LoggedRun& run = out[f[size_t(cLabel)]][std::stoi(f[size_t(cRepeat)])];
      double t = std::stod(f[size_t(cTime)]), spp = std::stod(f[size_t(cSpp)]);
      for (const auto& [name, c] : columns)
        if (!f[size_t(c)].empty()) {
          double v = std::stod(f[size_t(c)]);
          run.byTime[name].emplace_back(t, v), run.bySpp[name].emplace_back(spp, v);
        }
      if (f[size_t(cFinal)] == "1") run.finished = true, run.seconds = t;
    } catch (const std::exception&) {
      continue;  // a field that is not a number: not a row a run wrote
    }
  }
  for (auto& [label, runs] : out)
    for (auto& [r, run] : runs) {
      for (auto& [name, curve] : run.byTime) std::sort(curve.begin(), curve.end());
      for (auto& [name, curve] : run.bySpp) std::sort(curve.begin(), curve.end());
    }
  return out;
}

std::string number(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return logNumber(v);
}

}  // namespace

VerdictInputs readVerdictInputs(const std::string& runDir) {
  nlohmann::json m = readMeta(runDir);
  VerdictInputs in;
  in.runDir = runDir;
  const auto& v = m["verdict"];
  in.settings.rankBy = v.value("rank_by", std::string("relmse"));
  in.settings.confidence = v.value("confidence", 0.95);
  in.settings.looks = v.value("looks", 1);
  in.settings.tileSize = v.value("tile_size", 8);
  in.settings.metric.trimFraction = v.value("trim_fraction", 1e-3f);
  in.settings.metric.relEpsilon = m.value("relmse_epsilon", 1e-2f);
  in.baseline = v.value("baseline", std::string());
  if (m.contains("repeat_plan") && m["repeat_plan"].is_object()) {
    const auto& p = m["repeat_plan"];
    in.plan.untilDecided = p.value("until_decided", false);
    in.plan.min = p.value("min", 2);
    in.plan.extendReference = p.value("extend_reference", false);
  }
  in.plan.repeats = m.value("repeats", 1);
  for (const auto& s : m["scenes"]) {
    VerdictInputs::Scene scene;
    scene.name = s.value("name", std::string());
    if (s.contains("crop") && s["crop"].is_array() && s["crop"].size() == 4)
      scene.crop = {s["crop"][0].get<int>(), s["crop"][1].get<int>(), s["crop"][2].get<int>(), s["crop"][3].get<int>()};
    if (s.contains("reference_chunks") && s["reference_chunks"].is_number_unsigned())
      scene.referenceChunks = s["reference_chunks"].get<uint64_t>();
    in.scenes.push_back(scene);
  }
  std::map<std::string, size_t> raw;  // a configuration's label -> its index among the configurations
  for (const auto& c : m["configurations"]) {
    std::string label = c.value("label", std::string());
    in.labels.push_back(label);
    if (c.contains("denoise") && c["denoise"].is_object()) {
      in.configurationOf.push_back(raw.at(c["denoise"].value("of", std::string())));
    } else {
      raw.emplace(label, raw.size());
      in.configurationOf.push_back(raw.at(label));
    }
  }
  return in;
}

SceneJudgement judgeRunScene(const VerdictInputs& in, size_t si, const std::vector<int>& limit) {
  const std::string& scene = in.scenes[si].name;
  auto ranked = findVerdictMetric(in.settings.rankBy);
  if (!ranked) throw std::runtime_error("unknown rank_by metric '" + in.settings.rankBy + "'");
  SceneEvidence e;
  fs::path dir(in.runDir);
  e.reference = readExr((dir / (scene + "__reference.exr")).string());
  fs::path variance = dir / (scene + "__reference_variance.exr");
  if (fs::exists(variance)) e.referenceVariance = readExr(variance.string());
  e.referenceChunks = in.scenes[si].referenceChunks;
  e.crop = in.scenes[si].crop;
  LoggedRuns logged = readLoggedRuns(in.runDir, scene);
  SceneJudgement out;
  out.scene = scene;
  VerdictSettings settings = in.settings;
  for (size_t i = 0; i < in.labels.size(); ++i) {
    const std::string& label = in.labels[i];
    size_t c = in.configurationOf[i];
    int most = limit.empty() ? in.plan.repeats : limit[c];
    ConfigurationEvidence ce;
    ce.label = label;
    std::map<std::string, std::pair<std::vector<Curve>, std::vector<Curve>>> curves;  // metric -> by time, by spp
    auto runs = logged.find(label);
    if (runs != logged.end())
      for (const auto& [r, run] : runs->second) {
        if (r >= most || !run.finished) continue;
        std::string path = imagePath(in.runDir, scene, label, r);
        if (!fs::exists(path)) continue;  // a run folder from before every repeat's image was kept
        ce.finals.push_back(readExr(path));
        ce.seconds.push_back(run.seconds);
        auto curve = run.byTime.find(ranked->correctedColumn);
        ce.curves.push_back(curve == run.byTime.end() ? Curve{} : curve->second);
        for (const auto& m : verdictMetrics()) {
          auto t = run.byTime.find(m.correctedColumn);
          auto n = run.bySpp.find(m.correctedColumn);
          if (t == run.byTime.end()) continue;
          curves[m.name].first.push_back(t->second), curves[m.name].second.push_back(n->second);
        }
      }
    if (ce.finals.empty()) continue;  // not run (yet), or skipped under --quick
    for (const auto& [metric, c] : curves) {
      out.curves[{label, metric}] = {meanCurve(c.first, settings.alpha()), meanCurve(c.second, settings.alpha())};
    }
    if (label == in.baseline) settings.baseline = e.configurations.size();
    e.configurations.push_back(std::move(ce));
    out.labels.push_back(label);
    out.repeats.push_back(int(e.configurations.back().finals.size()));
    out.judged.configurationOf.push_back(c);
  }
  if (e.configurations.empty()) throw std::runtime_error(scene + ": no finished run to judge in " + in.runDir);
  out.judged.verdict = judgeScene(e, settings);
  for (const auto& m : verdictMetrics()) {
    if (m.crop && e.crop.empty()) continue;
    for (size_t i = 0; i < e.configurations.size(); ++i) out.metrics[m.name].push_back(estimateMetric(e, i, m.name, settings));
  }
  return out;
}

void writeVerdictFiles(const VerdictInputs& in, const std::vector<SceneJudgement>& scenes) {
  std::ostringstream verdict, pairs, metrics;
  verdict << "scene,label,metric,value,ci_low,ci_high,rank_group,decided,repeats,raw_value,time_s,efficiency,"
             "efficiency_low,efficiency_high,speedup,speedup_low,speedup_high,time_to_target_s,time_to_target_low_s,"
             "time_to_target_high_s,baseline\n";
  pairs << "scene,metric,better,worse,difference,difference_low,difference_high,p,p_holm,decided,adjacent,"
           "reference_share,repeats_better,repeats_worse,reason\n";
  metrics << "scene,label,metric,value,ci_low,ci_high,raw_value,repeats\n";
  for (const SceneJudgement& s : scenes) {
    const SceneVerdict& v = s.judged.verdict;
    const std::string& m = v.metric;
    size_t base = 0;
    for (size_t i = 0; i < s.labels.size(); ++i)
      if (s.labels[i] == in.baseline) base = i;
    for (size_t i : v.order) {
      const ConfigurationVerdict& c = v.configurations[i];
      const Estimate& e = c.estimate;
      verdict << csvField(s.scene) << "," << csvField(s.labels[i]) << "," << m << "," << number(displayValue(m, e.value))
              << "," << number(displayValue(m, e.low)) << "," << number(displayValue(m, e.high)) << ","
              << c.rankGroup() << "," << (c.decided ? "true" : "false") << "," << e.repeats << ","
              << number(displayValue(m, e.raw)) << "," << number(c.seconds);
      for (double x : {c.efficiency, c.efficiencyLow, c.efficiencyHigh, c.speedup, c.speedupLow, c.speedupHigh,
                       c.timeToTarget, c.timeToTargetLow, c.timeToTargetHigh})
        verdict << "," << number(x);
      verdict << "," << csvField(s.labels[base]) << "\n";
    }
    for (const PairComparison& p : v.pairs) {
      pairs << csvField(s.scene) << "," << m << "," << csvField(s.labels[p.a]) << "," << csvField(s.labels[p.b]);
      for (double x : {p.difference, p.low, p.high, p.p, p.pAdjusted}) pairs << "," << number(x);
      pairs << "," << (p.decided ? "true" : "false") << "," << (p.adjacent ? "true" : "false") << ","
            << number(p.referenceShare) << "," << s.repeats[p.a] << "," << s.repeats[p.b] << ","
            << csvField(p.adjacent ? undecidedReason(p, s.repeats[p.a], s.repeats[p.b], in.plan) : "") << "\n";
    }
    for (const auto& [name, estimates] : s.metrics)
      for (size_t i = 0; i < estimates.size(); ++i) {
        const Estimate& e = estimates[i];
        metrics << csvField(s.scene) << "," << csvField(s.labels[i]) << "," << name << ","
                << number(displayValue(name, e.value)) << "," << number(displayValue(name, e.low)) << ","
                << number(displayValue(name, e.high)) << "," << number(displayValue(name, e.raw)) << "," << e.repeats
                << "\n";
      }
  }
  std::ostringstream curves;
  curves << "scene,label,metric,x,x_value,mean,low,high\n";
  for (const SceneJudgement& s : scenes)
    for (const auto& [key, both] : s.curves)
      for (int byTime = 1; byTime >= 0; --byTime) {
        const MeanCurve& c = byTime ? both.first : both.second;
        for (size_t k = 0; k < c.x.size(); ++k)
          curves << csvField(s.scene) << "," << csvField(key.first) << "," << key.second << ","
                 << (byTime ? "time_s" : "spp") << "," << number(c.x[k]) << ","
                 << number(displayValue(key.second, c.mean[k])) << "," << number(displayValue(key.second, c.low[k]))
                 << "," << number(displayValue(key.second, c.high[k])) << "\n";
      }
  fs::path dir(in.runDir);
  writeTextFile((dir / "verdict_curves.csv").string(), curves.str());
  writeTextFile((dir / "verdict_metrics.csv").string(), metrics.str());
  writeTextFile((dir / "verdict_pairs.csv").string(), pairs.str());
  writeTextFile((dir / "verdict.csv").string(), verdict.str());
}

void recordVerdictSettings(const VerdictInputs& in) {
  nlohmann::json m = readMeta(in.runDir);
  m["verdict"]["rank_by"] = in.settings.rankBy;
  m["verdict"]["confidence"] = in.settings.confidence;
  m["verdict"]["baseline"] = in.baseline;
  writeTextFile((fs::path(in.runDir) / "meta.json").string(),
                m.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

std::string verdictSummary(const VerdictInputs& in, const std::vector<SceneJudgement>& scenes) {
  std::ostringstream out;
  const double level = 100 * in.settings.confidence;
  for (const SceneJudgement& s : scenes) {
    const SceneVerdict& v = s.judged.verdict;
    out << "verdict " << s.scene << " (by " << v.metric << (v.referenceVarianceKnown ? ", corrected for the reference" : "")
        << ", " << level << " % family-wise):";
    for (size_t i : v.order) {
      const auto& c = v.configurations[i];
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.3g", displayValue(v.metric, c.estimate.value));
      out << "  " << c.rankGroup() << ". " << s.labels[i] << " " << buf;
    }
    out << "\n";
    for (const PairComparison& p : v.pairs)
      if (p.adjacent && !p.decided)
        out << "  undecided: " << s.labels[p.a] << " vs " << s.labels[p.b] << ": "
            << undecidedReason(p, s.repeats[p.a], s.repeats[p.b], in.plan) << "\n";
  }
  return out.str();
}

}  // namespace lb
