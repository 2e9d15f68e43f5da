// `lightbench render`: load, render within a budget, write EXR + PNG + resolved
// configuration, print a summary. Output files appear only after a complete
// render, each through a temporary name and a rename.
#include <tbb/global_control.h>
#include <filesystem>
#include <iostream>
#include <sstream>
#include "core/scene_loader.h"
#include "experiments/cli/commands.h"
#include "integrators/registry.h"
#include "integrators/render_loop.h"

namespace lb {

namespace {

// The integrator's YAML node: the scene's (if it names the same integrator)
// with --set overrides applied.
struct IntegratorChoice {
  std::string name;
  YAML::Node params{YAML::NodeType::Map};
  std::vector<std::string> overridden;
  int line = 0;
};

IntegratorChoice chooseIntegrator(const SceneFile& sf, const RenderArgs& args) {
  IntegratorChoice c;
  std::string sceneName = "path";
  if (sf.integrator) {
    if (sf.integrator["name"]) sceneName = sf.integrator["name"].as<std::string>();
    c.line = sf.integrator.Mark().line + 1;
  }
  c.name = args.integrator.empty() ? sceneName : args.integrator;
  if (sf.integrator && c.name == sceneName)
    for (auto it = sf.integrator.begin(); it != sf.integrator.end(); ++it)
      if (it->first.as<std::string>() != "name") c.params[it->first.as<std::string>()] = it->second;
  for (const std::string& kv : args.overrides) {
    auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ConfigError("command line", 0, "--set " + kv, "expected key=value");
    std::string key = kv.substr(0, eq);
    try {
      c.params[key] = YAML::Load(kv.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw ConfigError("command line", 0, "--set " + key, "malformed value: " + e.msg);
    }
    c.overridden.push_back(key);
  }
  return c;
}

std::string stemPath(const std::string& exr) {
  std::filesystem::path p(exr);
  return (p.parent_path() / p.stem()).string();
}

void printSummary(const RenderReport& rep, const Film& film) {
  std::cerr << "done: " << rep.seconds << " s (preprocess " << rep.preprocessSeconds << " s), " << rep.passes
            << " spp, " << double(rep.rays) / std::max(rep.seconds - rep.preprocessSeconds, 1e-9) * 1e-6
            << " Mrays/s, NaN/Inf samples: " << rep.nonFinite << "\n";
  // A budget shorter than the preprocess still renders one pass: say so, or
  // an equal-time comparison would silently be unequal.
  std::string over = overBudgetMessage(rep);
  if (!over.empty()) std::cerr << "warning: " << over << "\n";
  for (const auto& s : film.firstNonFinite())
    std::cerr << "  non-finite sample: --pixel " << s.x << "," << s.y << " --sample " << s.sampleIndex << "\n";
}

int render(const RenderArgs& args) {
  YAML::Node sceneOverrides(YAML::NodeType::Map);
  if (args.worldScale > 0) sceneOverrides["world_scale"] = args.worldScale;
  SceneFile sf = loadScene(args.scene, sceneOverrides);
  IntegratorChoice choice = chooseIntegrator(sf, args);
  Params params(choice.params, args.scene, "integrator");
  for (const auto& k : choice.overridden) params.markOverridden(k);
  auto integrator = makeIntegrator(choice.name, params, args.scene, choice.line);

  std::unique_ptr<tbb::global_control> threads;
  if (args.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(args.threads));

  const Camera& cam = sf.scene->camera;
  if (!args.replayPixel.empty() || args.replaySample >= 0) {
    int x = -1, y = -1;
    if (std::sscanf(args.replayPixel.c_str(), "%d,%d", &x, &y) != 2 || x < 0 || y < 0 || x >= cam.width() ||
        y >= cam.height() || args.replaySample < 0)
      throw ConfigError("command line", 0, "--pixel", "replay needs --pixel X,Y inside the image and --sample I");
    enableFlushToZeroOnAllThreads();
    auto sampler = makeSampler(sf.sampler, args.seed);
    integrator->preprocess(*sf.scene, *sampler);
    auto value = integrator->replaySample(*sf.scene, *sampler, x, y, uint64_t(args.replaySample));
    if (!value) {
      std::cerr << "error: integrator '" << choice.name << "' cannot replay single samples\n";
      return 1;
    }
    std::cout << "pixel " << x << "," << y << " sample " << args.replaySample << ": " << value->r << " " << value->g
              << " " << value->b << "\n";
    return 0;
  }

  std::string output = args.output.empty() ? std::filesystem::path(args.scene).stem().string() + ".exr" : args.output;
  std::filesystem::path outDir = std::filesystem::path(output).parent_path();
  if (!outDir.empty() && !std::filesystem::is_directory(outDir))
    throw ConfigError("command line", 0, "--output", "folder does not exist: " + outDir.string());

  RenderOptions options;
  options.seed = args.seed;
  options.budget.spp = args.spp;
  options.budget.seconds = args.seconds;
  if (options.budget.spp == 0 && options.budget.seconds == 0) options.budget.spp = 16;
  options.progress = !args.quiet;

  Film film(cam.width(), cam.height());
  RenderReport rep = renderLoop(*sf.scene, *integrator, film, sf.sampler, options);

  YAML::Node resolved;
  resolved["lightbench"] = versionString();
  resolved["scene_file"] = args.scene;
  resolved["scene"] = loadYamlFile(args.scene);
  YAML::Node integ = params.resolved();
  integ["name"] = choice.name;
  resolved["integrator"] = integ;
  resolved["sampler"]["type"] = sf.sampler.type;
  resolved["sampler"]["strata"] = sf.sampler.strata;
  resolved["seed"] = args.seed;
  resolved["spp"] = rep.passes;
  resolved["threads"] = args.threads;
  resolved["seconds"] = rep.seconds;
  if (rep.budgetSeconds > 0) resolved["over_budget_seconds"] = rep.overBudgetSeconds();
  resolved["non_finite_samples"] = rep.nonFinite;
  YAML::Emitter emitter;
  emitter << resolved;

  Image image = film.image();
  std::string stem = stemPath(output);
  writeExr(output, image);
  writePng(stem + ".png", image);
  writeTextFile(stem + ".config.yaml", std::string(emitter.c_str()) + "\n");
  std::vector<std::string> extra = integrator->writeExtraOutputs(stem);
  printSummary(rep, film);
  std::cerr << "wrote " << output << ", " << stem << ".png, " << stem << ".config.yaml";
  if (!extra.empty()) std::cerr << " and " << extra.size() << " more (" << extra.front() << " …)";
  std::cerr << "\n";
  return 0;
}

}  // namespace

int runRender(const RenderArgs& args) {
  return withErrorExitCodes([&] { return render(args); });
}

}  // namespace lb
