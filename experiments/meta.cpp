#include "experiments/meta.h"
#include "experiments/reference.h"
#include <OpenEXR/OpenEXRConfig.h>
#include <OpenMesh/Core/System/config.h>
#include <embree3/rtcore_config.h>
#include <flann/config.h>
#include <glm/detail/setup.hpp>
#include <tbb/version.h>
#include <unistd.h>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include "core/image.h"
#include "integrators/registry.h"

namespace lb {

namespace {

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else out += c;
    }
  }
  return out + "\"";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}


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

std::string write(const RunMeta& m, const Experiment& e, bool finished) {
  std::ostringstream j;
  std::time_t now = std::time(nullptr);
  char ts[32];
  std::strftime(ts, sizeof ts, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  j << "{\n";
  j << "  \"experiment\": " << jsonString(e.name) << ",\n";
  j << "  \"experiment_file\": " << jsonString(e.file) << ",\n";
  j << "  \"lightbench\": " << jsonString(std::string(LIGHTBENCH_VERSION)) << ",\n";
  j << "  \"git_commit\": " << jsonString(LIGHTBENCH_GIT) << ",\n";
  j << "  \"started\": " << jsonString(m.started) << ",\n";
  j << "  \"experiment_hash\": " << jsonString(m.experimentHash) << ",\n";
  j << "  \"finished\": " << (finished ? jsonString(ts) : "null") << ",\n";
  j << "  \"machine\": {\"host\": " << jsonString(hostName()) << ", \"cpu\": " << jsonString(cpuModel())
    << ", \"cores\": " << std::thread::hardware_concurrency() << "},\n";
  j << "  \"threads_per_run\": " << m.threadsPerRun << ",\n  \"jobs\": " << m.jobs << ",\n";
  j << "  \"budget\": {\"seconds\": " << e.budget.seconds << ", \"spp\": " << e.budget.spp << "},\n";
  j << "  \"repeats\": " << e.repeats << ",\n  \"seeds\": [";
  for (int r = 0; r < e.repeats; ++r) j << (r ? ", " : "") << e.seed + uint64_t(r) * 7919;
  j << "],\n  \"metrics\": [";
  for (size_t i = 0; i < e.metrics.size(); ++i) j << (i ? ", " : "") << jsonString(e.metrics[i]);
  j << "],\n  \"relmse_epsilon\": " << e.metricSettings.relEpsilon
    << ",\n  \"outlier_percentile\": " << e.metricSettings.outlierPercentile << ",\n";
  j << "  \"scenes\": [";
  for (size_t i = 0; i < e.scenes.size(); ++i) {
    const auto& s = e.scenes[i];
    auto key = m.referenceKeys.find(s.name);
    j << (i ? ",\n    " : "\n    ") << "{\"name\": " << jsonString(s.name) << ", \"file\": " << jsonString(s.path)
      << ", \"overrides\": " << jsonString(flowYaml(s.overrides)) << ", \"reference\": "
      << jsonString(key == m.referenceKeys.end() ? "" : key->second) << ", \"reference_integrator\": "
      << jsonString(s.reference.file.empty() ? s.reference.integrator + " " + flowYaml(s.reference.params) + " " +
                                                   referenceBudget(s.reference)
                                             : "file")
      << ", \"reference_used\": " << jsonString(m.referenceUsed.count(s.name) ? m.referenceUsed.at(s.name) : "")
      << ", \"reference_rmse_floor\": "
      << (m.referenceRmseFloor.count(s.name) && std::isfinite(m.referenceRmseFloor.at(s.name))
              ? number(m.referenceRmseFloor.at(s.name))
              : std::string("null"))
      << ", \"crop\": " << (s.crop.empty() ? std::string("null") : "[" + std::to_string(s.crop.x0) + ", " +
                                                                   std::to_string(s.crop.y0) + ", " +
                                                                   std::to_string(s.crop.x1) + ", " +
                                                                   std::to_string(s.crop.y1) + "]")
      << "}";
  }
  j << "\n  ],\n  \"configurations\": [";
  for (size_t i = 0; i < e.configurations.size(); ++i) {
    const auto& c = e.configurations[i];
    Params p(c.params, e.file, "configurations");
    makeIntegrator(c.integrator, p);  // resolves defaults
    YAML::Node resolved = p.resolved();
    j << (i ? ",\n    " : "\n    ") << "{\"label\": " << jsonString(c.label) << ", \"integrator\": "
      << jsonString(c.integrator) << ", \"resolved_parameters\": " << jsonString(flowYaml(resolved)) << "}";
  }
  j << "\n  ],\n  \"libraries\": {\"embree\": " << jsonString(RTC_VERSION_STRING) << ", \"tbb\": "
    << jsonString(TBB_VERSION_STRING) << ", \"openexr\": " << jsonString(OPENEXR_VERSION_STRING)
    << ", \"glm\": " << GLM_VERSION << ", \"openmesh\": " << jsonString(std::to_string(OM_VERSION >> 16) + "." + std::to_string((OM_VERSION >> 8) & 0xff))
    << ", \"flann\": " << jsonString(FLANN_VERSION_)
    << ", \"yaml-cpp\": \"0.7 (Debian 12's package; the library has no version macro)\"},\n";
  j << "  \"experiment_source\": " << jsonString(flowYaml(e.source)) << "\n}\n";
  return j.str();
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

void finishMeta(const RunMeta& m, const Experiment& e, const std::string& runDir) {
  writeTextFile((std::filesystem::path(runDir) / "meta.json").string(), write(m, e, true));
}

}  // namespace lb
