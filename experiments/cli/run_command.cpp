// `lightbench run`: load and check the experiment, then hand it to the runner.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include "core/params.h"
#include "core/scene_import.h"
#include "experiments/cli/commands.h"
#include "core/error.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/report_step.h"
#include "experiments/runner.h"
#include "experiments/verdict/run_folder.h"

namespace lb {

int runExperimentCommand(const RunArgs& args) {
  return withErrorExitCodes([&] {
    ExperimentOptions eo;
    eo.quick = args.quick;
    // `lightbench run scene.yaml`: say which command was meant.
    bool scene = isImportedScenePath(args.experiment);
    if (!scene) {
      YAML::Node root = loadYamlFile(args.experiment);
      scene = root.IsMap() && !root["configurations"] && (root["camera"] || root["shapes"]);
    }
    if (scene)
      throw ConfigError(args.experiment, 0, "", "this is a scene, not an experiment: render it with 'lightbench render " +
                                                    args.experiment + "'");
    if (args.farm && args.jobs > 1)
      throw ConfigError(args.experiment, 0, "--jobs", "under MPI each rank runs one run at a time; start more ranks instead");
    Experiment e = loadExperiment(args.experiment, eo);
    // Before any reference renders: the results folder (created if missing).
    checkWritableFolder("--results", args.results);
    // Its two folders, if something else already has their names: found after
    // the reference had rendered, with exit 1 and a raw filesystem error.
    for (const std::filesystem::path& sub : {std::filesystem::path(args.results) / e.name,
                                             std::filesystem::path(args.results) / "references"}) {
      std::error_code ec;
      if (std::filesystem::exists(sub, ec) && !std::filesystem::is_directory(sub, ec))
        throw flagError("--results", sub.string() + " is not a folder (the run writes one there); move it");
    }
    RunnerOptions ro;
    ro.resultsRoot = args.results;
    ro.resume = args.resume;
    ro.jobs = args.jobs;
    ro.report = !args.noReport;
    ro.python = args.python;
    ro.threads = args.threads;
    ro.mixedMachines = args.mixedMachines;
    ro.farm = args.farm;
    runExperiment(e, ro);
    return 0;
  });
}

int verdictCommand(const VerdictArgs& args) {
  return withErrorExitCodes([&] {
    std::filesystem::path meta = std::filesystem::path(args.run) / "meta.json";
    if (!std::filesystem::is_directory(args.run) || !std::filesystem::exists(meta))
      throw ConfigError(args.run, 0, "run", "not a run folder (no meta.json): give results/NAME/RUN-ID");
    VerdictInputs inputs;
    try {
      inputs = readVerdictInputs(args.run);
    } catch (const std::runtime_error& e) {
      throw ConfigError(meta.string(), 0, "verdict", e.what());
    }
    if (!args.rankBy.empty()) {
      auto m = findVerdictMetric(args.rankBy);
      if (!m) throw ConfigError(args.run, 0, "--rank-by", "unknown metric '" + args.rankBy + "' (rmse, relmse, relmse_trimmed, rmse_crop, relmse_crop)");
      for (const auto& s : inputs.scenes)
        if (m->crop && s.crop.empty())
          throw ConfigError(args.run, 0, "--rank-by", "'" + args.rankBy + "' needs a crop; scene '" + s.name + "' has none");
      inputs.settings.rankBy = args.rankBy;
    }
    if (!args.baseline.empty()) {
      if (std::find(inputs.labels.begin(), inputs.labels.end(), args.baseline) == inputs.labels.end())
        throw ConfigError(args.run, 0, "--baseline", "no configuration is labelled '" + args.baseline + "'");
      inputs.baseline = args.baseline;
    }
    if (args.confidence > 0) inputs.settings.confidence = args.confidence;
    std::vector<SceneJudgement> judged;
    for (size_t si = 0; si < inputs.scenes.size(); ++si) judged.push_back(judgeRunScene(inputs, si));
    writeVerdictFiles(inputs, judged);
    recordVerdictSettings(inputs);
    std::cerr << verdictSummary(inputs, judged);
    if (!args.noReport) {
      std::string problem = runReportScript(reportInterpreter(args.python), args.run, false);
      if (!problem.empty()) std::cerr << "warning: no report: " << problem << "\n";
      else std::cerr << "report: " << (std::filesystem::path(args.run) / "report.html").string() << "\n";
    }
    return 0;
  });
}

int serveExperimentCommand(const RunArgs& args) {
  return withErrorExitCodes([&] {
    ExperimentOptions eo;
    eo.quick = args.quick;
    RunnerOptions ro;
    ro.resultsRoot = args.results;
    ro.threads = args.threads;
    ro.farm = args.farm;
    return serveExperiment(args.experiment, eo, ro);
  });
}

}  // namespace lb
