// Command-line front end (CLI11): `lightbench render`, `lightbench integrators`.
#include <CLI/CLI.hpp>
#include <iostream>
#include "experiments/cli/commands.h"
#include "core/error.h"
#include "integrators/registry.h"

namespace lb {

int withErrorExitCodes(const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

std::string versionString() { return std::string("lightbench ") + LIGHTBENCH_VERSION + " (" + LIGHTBENCH_GIT + ")"; }

int lightbenchMain(int argc, char** argv) {
  CLI::App app{"lightbench: a research testbed for light transport.\n"
               "Renders YAML scenes with interchangeable integrators and measures their error against time."};
  app.set_version_flag("--version", versionString());
  app.require_subcommand(1);

  RenderArgs r;
  CLI::App* render = app.add_subcommand("render", "Render one scene to an EXR (plus a PNG preview and the resolved configuration).");
  render->add_option("scene", r.scene, "Scene file (YAML)")->required();
  render->add_option("--integrator", r.integrator, "Integrator name (default: the scene's, else 'path'); see 'lightbench integrators'");
  render->add_option("--set", r.overrides, "Integrator parameter override key=value (repeatable), e.g. --set mis=balance");
  auto* spp = render->add_option("--spp", r.spp, "Samples per pixel (default 16 when no --time is given)");
  render->add_option("--time", r.seconds, "Time budget in seconds, preprocessing included")->excludes(spp);
  render->add_option("--seed", r.seed, "Random seed; the same seed gives the same image bit for bit at any thread count");
  render->add_option("--threads", r.threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  render->add_option("-o,--output", r.output, "Output EXR path (default: <scene name>.exr); the PNG and <name>.config.yaml go beside it");
  render->add_option("--pixel", r.replayPixel, "Replay one sample: pixel X,Y (with --sample); prints its value, writes nothing");
  render->add_option("--sample", r.replaySample, "Replay one sample: sample index (with --pixel)");
  render->add_flag("-q,--quiet", r.quiet, "No progress line");
  render->add_option("--world-scale", r.worldScale, "Scale the whole scene (camera, lights, radii) by this factor; replaces the scene's world_scale key")
      ->check(CLI::PositiveNumber);

  RunArgs run;
  CLI::App* runCmd = app.add_subcommand("run", "Run an experiment: every configuration against a reference, error vs time logged, plotted and reported.");
  runCmd->add_option("experiment", run.experiment, "Experiment file (YAML), e.g. experiments/quickstart.yaml")->required();
  runCmd->add_flag("--quick", run.quick, "A quarter of the budget and reference samples, one repeat; integrators not built yet are skipped with a warning");
  runCmd->add_flag("--resume", run.resume, "Continue the latest run of this experiment: finished runs are kept, unfinished ones redone");
  runCmd->add_option("--jobs", run.jobs, "Runs at once, each with cores/jobs threads (default 1: one run on all cores, the honest setting for timings)")->check(CLI::PositiveNumber);
  runCmd->add_option("--results", run.results, "Folder for run outputs and cached references (default: results)");
  runCmd->add_flag("--no-report", run.noReport, "Skip the plots and HTML report");

  app.add_subcommand("integrators", "List the available integrators.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (app.got_subcommand("integrators")) {
    for (const auto& e : integratorRegistry()) std::cout << e.name << "\t" << e.summary << "\n";
    return 0;
  }
  if (app.got_subcommand("run")) return runExperimentCommand(run);
  return runRender(r);
}

}  // namespace lb
