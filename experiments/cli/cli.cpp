// Command-line front end (CLI11): `lightbench render`, `lightbench integrators`.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <iterator>
#include <limits>
#include "experiments/cli/commands.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/experiment.h"
#include "core/error.h"
#include "core/params.h"
#include "integrators/registry.h"
#include "integrators/registry_docs.h"

namespace lb {

int withErrorExitCodes(const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const RemoteFailure& e) {  // a worker rank's error, already formatted
    std::cerr << "error: " << e.what() << "\n";
    return e.exitCode;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory (std::bad_alloc)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

std::string versionString() { return std::string("lightbench ") + LIGHTBENCH_VERSION + " (" + LIGHTBENCH_GIT + ")"; }

int lightbenchMain(int argc, char** argv, Farm* farm) {
  const bool worker = farm && farm->isWorker();
  CLI::App app{"lightbench: a research testbed for light transport.\n"
               "Renders YAML scenes with interchangeable integrators and measures their error against time."};
  app.set_version_flag("--version", versionString());
  app.require_subcommand(1);

  RenderArgs r;
  CLI::App* render = app.add_subcommand("render", "Render one scene to an EXR (plus a PNG preview and the resolved configuration).");
  render->add_option("scene", r.scene, "Scene file: YAML, Mitsuba 0.5/0.6/3 XML (.xml) or pbrt-v4 (.pbrt)")->required();
  render->add_option("--integrator", r.integrator, "Integrator name (default: the scene's, else 'path'); see 'lightbench integrators'");
  render->add_option("--set", r.overrides, "Integrator parameter override key=value (repeatable), e.g. --set mis=balance");
  // Every value is checked as typed (flag_checks.h): 0, negative, NaN or
  // infinite budgets would render the default or forever.
  auto* spp = render->add_option("--spp", r.spp, "Samples per pixel (default 16 when no --time is given)")
                  ->check(renderFlagCheck("--spp"));
  render->add_option("--time", r.seconds, "Time budget in seconds, preprocessing included")
      ->excludes(spp)
      ->check(renderFlagCheck("--time"));
  render->add_option("--seed", r.seed, "Random seed; the same seed gives the same image bit for bit at any thread count")
      ->check(renderFlagCheck("--seed"));
  render->add_option("--threads", r.threads, "Worker threads (default: all cores)")
      ->check(renderFlagCheck("--threads"));
  render->add_option("-o,--output", r.output,
                     "Output: NAME.exr (default: <scene name>.exr; the PNG preview and NAME.config.yaml go beside it), "
                     "or NAME.png for the preview only")
      ->check(outputFileName());
  render->add_option("--resolution", r.resolution, "Film size WIDTHxHEIGHT, e.g. 640x480 (replaces the scene's film size)")
      ->check(renderFlagCheck("--resolution"));
  render->add_option("--aov", r.aovs, "Extra EXR layers, comma-separated: albedo, normal, depth (first hit), variance "
                                      "(of each pixel's estimate), spp (samples per pixel)")
      ->delimiter(',')
      ->check(CLI::IsMember(aovNames()));
  render->add_option("--crop", r.crop,
                     "Render only pixels X0,Y0,X1,Y1 of the film ([X0, X1) x [Y0, Y1), after --resolution): the "
                     "output is that window, each pixel estimating what it does in the full render")
      ->check(renderFlagCheck("--crop"));
  render->add_option("--sampler", r.sampler, "Sampler type, replacing the scene's: independent, stratified, sobol, zsobol, halton")
      ->check(CLI::IsMember(std::vector<std::string>(std::begin(lb::SamplerTypes), std::end(lb::SamplerTypes))));
  render->add_option("--exposure", r.exposure, "Exposure of the PNG preview in stops (the EXR is never scaled)")
      ->check(renderFlagCheck("--exposure"));
  render->add_option("--pixel", r.replayPixel, "Replay one sample: pixel X,Y (with --sample); prints its value, writes nothing")
      ->check(pixelCoordinates());
  render->add_option("--sample", r.replaySample, "Replay one sample: sample index (with --pixel)")
      ->check(intInRange(0, std::numeric_limits<long long>::max(), "sample index"));
  auto* adaptive = render->add_flag(
      "--adaptive", r.adaptive,
      "Adaptive sampling: after uniform passes, samples go to pixels by their estimated relative error; one half of "
      "the samples decides, the other (unbiased) half is the image");
  render->add_option("--adaptive-passes", r.adaptivePasses, "Uniform passes before adapting (default 8)")
      ->needs(adaptive)
      ->check(renderFlagCheck("--adaptive-passes"));
  render->add_option("--adaptive-target", r.adaptiveTarget,
                     "Relative error at which a pixel gets no more samples (default 0: none; all there: stop early)")
      ->needs(adaptive)
      ->check(renderFlagCheck("--adaptive-target"));
  render->add_flag("-q,--quiet", r.quiet, "No progress line");
  auto* distributed = render->add_flag(
      "--distributed", r.distributed,
      "Render as independent seeded chunks of --chunk-spp passes, averaged in chunk order; under mpirun the chunks "
      "are spread over the ranks, with the same bits for any number of ranks (path, light, bdpt, direct, vcm mode=bpt or lvc)");
  render->add_option("--chunk-spp", r.chunkSpp, "Passes per chunk with --distributed (default 16; --spp must be a multiple)")
      ->needs(distributed)
      ->check(renderFlagCheck("--chunk-spp"));
  render->add_flag("--strict", r.strict, "An imported (.xml, .pbrt) scene's unsupported elements are errors, not warnings");
  render->add_option("--world-scale", r.worldScale, "Scale the whole scene (camera, lights, radii) by this factor; replaces the scene's world_scale key")
      ->check(positiveFinite(""));

  RunArgs run;
  CLI::App* runCmd = app.add_subcommand("run", "Run an experiment: every configuration against a reference, error vs time logged, plotted and reported.");
  runCmd->add_option("experiment", run.experiment, "Experiment file (YAML), e.g. experiments/quickstart.yaml")->required();
  runCmd->add_flag("--quick", run.quick, "A quarter of the budget and reference samples, one repeat; integrators not built yet are skipped with a warning");
  runCmd->add_flag("--resume", run.resume, "Continue the latest run of this experiment: finished runs are kept, unfinished ones redone");
  runCmd->add_option("--jobs", run.jobs, "Runs at once, each with cores/jobs threads (default 1: one run on all cores, the honest setting for timings)")
      ->check(intInRange(1, std::numeric_limits<int>::max(), "runs at once"));
  runCmd->add_option("--results", run.results, "Folder for run outputs and cached references (default: results)");
  runCmd->add_flag("--no-report", run.noReport, "Skip the plots and HTML report");
  runCmd->add_option("--threads", run.threads, "Threads per run (default: the cores shared among the runs at once; under MPI, a node's cores shared among its worker ranks)")
      ->check(intInRange(1, std::numeric_limits<int>::max(), "threads per run"));
  runCmd->add_flag("--mixed-machines", run.mixedMachines, "Let the report compare runs timed on different kinds of machines (CPU model or threads; an MPI sweep over a mixed cluster)");
  runCmd->add_option("--python", run.python, "Interpreter for the report (default: $LIGHTBENCH_PYTHON, else /usr/bin/python3); needs matplotlib");

  VerdictArgs verdict;
  CLI::App* verdictCmd = app.add_subcommand("verdict", "Judge a finished run folder again (rank groups, intervals, speed-ups), with other settings if given, and rewrite its report.");
  verdictCmd->add_option("run", verdict.run, "A run folder, results/NAME/RUN-ID")->required();
  verdictCmd->add_option("--rank-by", verdict.rankBy, "Rank by this metric: rmse, relmse, relmse_trimmed, rmse_crop, relmse_crop");
  verdictCmd->add_option("--baseline", verdict.baseline, "The label speed-ups are measured against");
  verdictCmd->add_option("--confidence", verdict.confidence, "Family-wise confidence of the rank groups and of the intervals (default: the run's)")
      ->check(numberInRange(0.5, 0.9999, "family-wise confidence"));
  verdictCmd->add_flag("--no-report", verdict.noReport, "Only the verdict files, no report");
  verdictCmd->add_option("--python", verdict.python, "Interpreter for the report (default: $LIGHTBENCH_PYTHON, else /usr/bin/python3)");

  std::string integratorName;
  bool markdown = false;
  CLI::App* integrators = app.add_subcommand("integrators", "List the integrators, or one integrator's keys with type, default, range and meaning.");
  integrators->add_option("name", integratorName, "An integrator's name: list its keys");
  integrators->add_flag("--markdown", markdown, "The key table as markdown (docs/integrators.md is this for every integrator)");
  std::string withProperty;
  integrators->add_option("--with", withProperty,
                          "The integrators with a property, as the docs list them: splits (--distributed), unbiased "
                          "(references), adaptive (--adaptive), replay (--pixel)")
      ->check(CLI::IsMember(integratorProperties()));
  std::string withoutProperty;
  integrators->add_option("--without", withoutProperty,
                          "The integrators without a property, each with the reason it gives (as docs/distributed.md "
                          "lists those that cannot be split)")
      ->check(CLI::IsMember(integratorProperties()));
  bool names = false, fillLists = false;
  integrators->add_flag("--names", names, "Every integrator's name on one line, as README.md lists them");
  integrators->add_flag("--fill-lists", fillLists,
                        "Copy markdown from standard input to standard output with every marked list of integrators "
                        "(<!-- integrators SPEC -->) as generated now (scripts/update-docs.sh uses it)");

  std::string shell;
  CLI::App* completion = app.add_subcommand("completion", "Print a shell completion script: source <(lightbench completion bash)");
  completion->add_option("shell", shell, "The shell (bash)")->required()->check(CLI::IsMember({"bash"}));

  r.farm = run.farm = farm;
  // A worker rank serves rank 0 until told to stop, with rank 0's exit code;
  // only rank 0 speaks to the user (its parse errors, help and version).
  auto serve = [&]() -> int {
    if (app.got_subcommand("run")) return serveExperimentCommand(run);
    if (app.got_subcommand("render") && r.distributed) return serveRender(r);
    return farm->serve([](const std::string&) -> std::string { throw std::runtime_error("no work to share"); });
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (worker) return farm->serve([](const std::string&) -> std::string { throw std::runtime_error("no work"); });
    // --help and --version are "errors" with exit code 0.
    if (e.get_exit_code() == 0) return app.exit(e);
    // One line, like every other bad input (CLI11's own exit() adds a second).
    std::string message = e.what();
    // A mistyped subcommand ("rendr"): CLI11 says only that one is required.
    if (argc > 1 && argv[1][0] != '-') {
      std::vector<std::string> names;
      std::string list;
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        names.push_back(sub->get_name());
        list += (list.empty() ? "" : ", ") + sub->get_name();
      }
      if (std::find(names.begin(), names.end(), argv[1]) == names.end()) {
        std::string hint = closestMatch(argv[1], names);
        message = "unknown subcommand '" + std::string(argv[1]) + "'" +
                  (hint.empty() ? "" : "; did you mean '" + hint + "'?") + " (subcommands: " + list + ")";
      }
    }
    // A mistyped flag ("--thread"): CLI11 lists what it did not expect.
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
      std::vector<CLI::App*> parsed = app.get_subcommands();
      const CLI::App* where = parsed.empty() ? &app : parsed.back();
      std::vector<std::string> flags;
      for (const CLI::Option* o : where->get_options())
        for (const std::string& name : o->get_lnames()) flags.push_back("--" + name);
      for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        arg = arg.substr(0, arg.find('='));
        if (arg.rfind("--", 0) != 0 || std::find(flags.begin(), flags.end(), arg) != flags.end()) continue;
        std::string hint = closestMatch(arg, flags);
        message = "unknown flag '" + arg + "'" + (hint.empty() ? "" : "; did you mean '" + hint + "'?") +
                  " (`lightbench " + (parsed.empty() ? std::string() : where->get_name() + " ") + "--help` lists them)";
        break;
      }
    }
    for (char& c : message)
      if (c == '\n') c = ' ';
    std::cerr << "error: " << message << "\n";
    return 2;
  }
  if (worker) return serve();
  if (app.got_subcommand("integrators")) {
    return withErrorExitCodes([&] {
      if (!withProperty.empty()) std::cout << integratorsWith(withProperty) << "\n";
      else if (!withoutProperty.empty()) std::cout << integratorsWithout(withoutProperty);
      else if (names) std::cout << integratorNames() << "\n";
      else if (fillLists) std::cout << withCurrentIntegratorLists(std::string(std::istreambuf_iterator<char>(std::cin), {}), "standard input");
      else if (!integratorName.empty()) std::cout << formatIntegratorKeys(integratorName, markdown);
      else if (markdown)
        for (const auto& e : integratorRegistry()) std::cout << formatIntegratorKeys(e.name, true) << "\n";
      else
        for (const auto& e : integratorRegistry()) std::cout << e.name << "\t" << e.summary << "\n";
      return 0;
    });
  }
  if (app.got_subcommand("run")) return runExperimentCommand(run);
  if (app.got_subcommand("verdict")) return verdictCommand(verdict);
  if (app.got_subcommand("completion")) {
    std::cout << bashCompletion(app);
    return 0;
  }
  return runRender(r);
}

}  // namespace lb
