#include "experiments/meta.h"
#include "experiments/reference.h"
#include "experiments/json_values.h"
#include <OpenEXR/OpenEXRConfig.h>
#include <OpenMesh/Core/System/config.h>
#include <embree3/rtcore_config.h>
#include <flann/config.h>
#include <glm/detail/setup.hpp>
#include <tbb/version.h>
#include <nlohmann/json.hpp>
#include <unistd.h>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>
#include "core/image.h"
#include "integrators/registry.h"

namespace lb {

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string hostName() {
  char buf[256] = {0};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

namespace {

std::string write(const RunMeta& m, const Experiment& e, bool finished) {
  using nlohmann::json;
  std::time_t now = std::time(nullptr);
  char ts[32];
  std::strftime(ts, sizeof ts, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  json j;
  j["experiment"] = e.name;
  j["experiment_file"] = e.file;
  j["lightbench"] = LIGHTBENCH_VERSION;
  j["git_commit"] = LIGHTBENCH_GIT;
  j["started"] = m.started;
  j["experiment_hash"] = m.experimentHash;
  j["finished"] = finished ? json(ts) : json(nullptr);
  j["machine"] = {{"host", hostName()}, {"cpu", cpuModel()}, {"cores", std::thread::hardware_concurrency()}};
  j["threads_per_run"] = m.threadsPerRun;
  j["jobs"] = m.jobs;
  j["ranks"] = m.ranks;  // MPI ranks (1: a single process); each row names its host and threads
  j["budget"] = {{"seconds", e.budget.seconds}, {"spp", e.budget.spp}};
  j["repeats"] = e.repeats;
  j["seeds"] = json::array();
  for (int r = 0; r < e.repeats; ++r) j["seeds"].push_back(e.seed + uint64_t(r) * 7919);
  j["metrics"] = e.metrics;
  j["relmse_epsilon"] = e.metricSettings.relEpsilon;
  j["repeat_plan"] = {{"until_decided", e.repeatPlan.untilDecided},
                      {"min", e.repeatPlan.untilDecided ? e.repeatPlan.min : e.repeats},
                      {"max", e.repeats},
                      {"extend_reference", e.repeatPlan.extendReference},
                      {"looks", e.repeatPlan.looks()}};
  // What experiments/verdict/run_folder.cpp reads back (and `lightbench verdict` may override).
  std::string baseline = e.baseline.empty() ? e.configurations.front().label : e.baseline;
  j["verdict"] = {{"rank_by", e.rankBy},
                  {"confidence", e.confidence},
                  {"baseline", baseline},
                  {"looks", int(e.repeatPlan.looks().size())},
                  {"trim_fraction", e.metricSettings.trimFraction},
                  {"tile_size", 8}};
  j["scenes"] = json::array();
  for (const auto& s : e.scenes) {
    auto key = m.referenceKeys.find(s.name);
    json scene = {{"name", s.name}, {"file", s.path}, {"overrides", yamlToJson(s.overrides)}};
    scene["reference"] = key == m.referenceKeys.end() ? "" : key->second;
    if (s.reference.file.empty())
      scene["reference_integrator"] = {{"name", s.reference.integrator},
                                       {"params", yamlToJson(s.reference.params)},
                                       {"budget", referenceBudget(s.reference)}};
    else
      scene["reference_integrator"] = "file";
    scene["reference_used"] = m.referenceUsed.count(s.name) ? m.referenceUsed.at(s.name) : "";
    scene["reference_exr"] = s.name + "__reference.exr";  // in the run folder
    auto floor = m.referenceRmseFloor.find(s.name);
    scene["reference_rmse_floor"] =
        floor != m.referenceRmseFloor.end() && std::isfinite(floor->second) ? json(floor->second) : json(nullptr);
    auto chunks = m.referenceChunks.find(s.name);
    scene["reference_chunks"] = chunks != m.referenceChunks.end() && chunks->second > 0 ? json(chunks->second) : json(nullptr);
    scene["reference_variance_exr"] = s.name + "__reference_variance.exr";  // absent when unknown
    scene["crop"] = s.crop.empty() ? json(nullptr) : json({s.crop.x0, s.crop.y0, s.crop.x1, s.crop.y1});
    j["scenes"].push_back(scene);
  }
  j["configurations"] = json::array();
  for (const auto& c : e.configurations) {
    Params p(c.params, e.file, "configurations");
    makeIntegrator(c.integrator, p);  // resolves defaults
    json conf = {{"label", c.label}, {"integrator", c.integrator}, {"resolved_parameters", yamlToJson(p.resolved())}};
    if (c.sampler) conf["sampler"] = {{"type", c.sampler->type}, {"strata", c.sampler->strata}, {"spp", c.sampler->spp}};
    if (c.adaptive.enabled)
      conf["adaptive"] = {{"passes", c.adaptive.passes}, {"target_relative_error", c.adaptive.targetRelativeError}};
    if (!c.sweepGroup.empty()) conf["sweep"] = {{"group", c.sweepGroup}, {"values", yamlToJson(c.sweepValues)}};
    for (const auto& entry : integratorRegistry())
      if (entry.name == c.integrator) conf["unbiased"] = entry.unbiased(c.params);
    j["configurations"].push_back(conf);
    // Its denoised snapshots are logged as a configuration of their own: a
    // filter's output is biased (it trades variance for bias).
    if (!c.denoise.empty()) {
      json denoised = conf;
      denoised["label"] = c.denoisedLabel();
      denoised["denoise"] = {{"filter", c.denoise}, {"of", c.label}};
      denoised["unbiased"] = false;
      j["configurations"].push_back(denoised);
    }
  }
  j["libraries"] = {{"embree", RTC_VERSION_STRING},
                    {"tbb", TBB_VERSION_STRING},
                    {"openexr", OPENEXR_VERSION_STRING},
                    {"glm", GLM_VERSION},
                    {"openmesh", std::to_string(OM_VERSION >> 16) + "." + std::to_string((OM_VERSION >> 8) & 0xff)},
                    {"flann", FLANN_VERSION_},
                    {"yaml-cpp", "0.7 (Debian 12's package; the library has no version macro)"},
                    {"nlohmann-json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                          std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                          std::to_string(NLOHMANN_JSON_VERSION_PATCH)}};
  j["experiment_source"] = yamlToJson(e.source);
  // Invalid UTF-8 (a label or path in another encoding) is replaced, not a throw without file or key.
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace

RunMeta startMeta(const Experiment& e, const std::string& runDir, int threadsPerRun, int jobs,
                  const std::string& experimentHash) {
  RunMeta m;
  m.experimentHash = experimentHash;
  std::time_t now = std::time(nullptr);
  char ts[32];
  std::strftime(ts, sizeof ts, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  m.started = ts;
  m.threadsPerRun = threadsPerRun;
  m.jobs = jobs;
  writeTextFile((std::filesystem::path(runDir) / "meta.json").string(), write(m, e, false));
  return m;
}

void writeMeta(const RunMeta& m, const Experiment& e, const std::string& runDir, bool finished) {
  writeTextFile((std::filesystem::path(runDir) / "meta.json").string(), write(m, e, finished));
}

std::string readExperimentHash(const std::string& runDir) {
  std::ifstream in(std::filesystem::path(runDir) / "meta.json");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || !j.contains("experiment_hash") || !j["experiment_hash"].is_string())
    return "";
  return j["experiment_hash"].get<std::string>();
}

}  // namespace lb
