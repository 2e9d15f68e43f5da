// `lightbench render`: load, render within a budget, write EXR + PNG + resolved
// configuration, print a summary. Output files appear only after a complete
// render, each through a temporary name and a rename.
#include <tbb/global_control.h>
#include <unistd.h>
#include <filesystem>
#include <iostream>
#include <sstream>
#include "core/scene_loader.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/flag_checks.h"
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

void checkIntegratorName(const std::string& name) {
  std::vector<std::string> names;
  for (const auto& e : integratorRegistry())
    if (e.name == name) return;
    else names.push_back(e.name);
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  std::string hint = closestMatch(name, names);
  throw flagError("--integrator", "unknown integrator '" + name + "' (available: " + list + ")" +
                                      (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
}

IntegratorChoice chooseIntegrator(const SceneFile& sf, const RenderArgs& args) {
  IntegratorChoice c;
  std::string sceneName = "path";
  if (sf.integrator) {
    c.line = sf.integrator.Mark().line + 1;
    if (YAML::Node n = sf.integrator["name"]) {
      if (!n.IsScalar())
        throw ConfigError(sf.path, n.Mark().line + 1, "integrator.name",
                          std::string("expected a string, got a ") + (n.IsSequence() ? "sequence" : "mapping"));
      sceneName = n.Scalar();
    }
  }
  c.name = args.integrator.empty() ? sceneName : args.integrator;
  if (sf.integrator && c.name == sceneName)
    for (auto it = sf.integrator.begin(); it != sf.integrator.end(); ++it)
      if (it->first.as<std::string>() != "name") c.params[it->first.as<std::string>()] = it->second;
  // Keys that define the integral (an imported scene's max_depth) hold for any integrator.
  c.params = withSharedIntegratorKeys(sf, c.params);
  for (const std::string& kv : args.overrides) {
    auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw flagError("--set", "expected key=value (e.g. --set max_depth=8), got '" + kv + "'");
    std::string key = kv.substr(0, eq);
    YAML::Node value;
    try {
      value = YAML::Load(kv.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw flagError("--set " + key, "malformed value: " + e.msg);
    }
    // An empty value loads as null, which every accessor reads as "use the
    // default": the override would silently do nothing.
    if (value.IsNull()) throw flagError("--set " + key, "empty value (expected " + key + "=value)");
    c.params[key] = value;
    c.overridden.push_back(key);
  }
  return c;
}

std::string stemPath(const std::string& exr) {
  std::filesystem::path p(exr);
  return (p.parent_path() / p.stem()).string();
}

// Every output path is checked before the render: a failure found only when
// writing would cost the whole render, and could leave the EXR without its
// PNG and configuration.
void checkOutputs(const std::string& output) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(output).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw flagError("--output", "folder does not exist: " + dir.string());
  if (!fs::is_directory(dir, ec)) throw flagError("--output", "not a folder: " + dir.string());
  checkWritableFolder("--output", dir);
  std::string stem = stemPath(output);
  for (const std::string& path : {output, stem + ".png", stem + ".config.yaml"})
    if (fs::is_directory(path, ec)) throw flagError("--output", "cannot write " + path + ": it is a directory");
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
  const bool replay = !args.replayPixel.empty() || args.replaySample >= 0;
  if (!args.replayPixel.empty() && args.replaySample < 0) throw flagError("--sample", "--pixel needs --sample I");
  if (args.replayPixel.empty() && args.replaySample >= 0) throw flagError("--pixel", "--sample needs --pixel X,Y");
  if (!args.integrator.empty()) checkIntegratorName(args.integrator);
  std::string output = args.output.empty() ? std::filesystem::path(args.scene).stem().string() + ".exr" : args.output;
  if (!replay) checkOutputs(output);

  YAML::Node sceneOverrides(YAML::NodeType::Map);
  if (args.worldScale > 0) {
    if (std::string problem = worldScaleProblem(args.worldScale); !problem.empty()) throw flagError("--world-scale", problem);
    sceneOverrides["world_scale"] = args.worldScale;
  }
  SceneLoadOptions loadOptions;
  loadOptions.strict = args.strict;
  SceneFile sf = loadScene(args.scene, sceneOverrides, loadOptions);
  IntegratorChoice choice = chooseIntegrator(sf, args);
  Params params(choice.params, args.scene, "integrator");
  for (const auto& k : choice.overridden) params.markOverridden(k);
  auto integrator = makeIntegrator(choice.name, params, args.scene, choice.line);
  if (!replay)
    for (const std::string& path : integrator->extraOutputPaths(stemPath(output))) {
      std::error_code ec;
      if (std::filesystem::is_directory(path, ec)) throw flagError("--output", "cannot write " + path + ": it is a directory");
    }

  std::unique_ptr<tbb::global_control> threads;
  if (args.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(args.threads));

  const Camera& cam = sf.scene->camera;
  if (replay) {
    int x = -1, y = -1;
    if (!parsePixel(args.replayPixel, x, y) || x >= cam.width() || y >= cam.height())
      throw flagError("--pixel", "must be a pixel X,Y inside the " + std::to_string(cam.width()) + "x" +
                                     std::to_string(cam.height()) + " film, got '" + args.replayPixel + "'");
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

  RenderOptions options;
  options.seed = args.seed;
  options.budget.spp = args.spp;
  options.budget.seconds = args.seconds;
  if (options.budget.spp == 0 && options.budget.seconds == 0) options.budget.spp = sf.sceneSpp ? sf.sceneSpp : 16;
  options.progress = !args.quiet;

  Film film(cam.width(), cam.height());
  RenderReport rep = renderLoop(*sf.scene, *integrator, film, sf.sampler, options);

  YAML::Node resolved;
  resolved["lightbench"] = versionString();
  resolved["scene_file"] = args.scene;
  resolved["scene"] = sf.description;
  if (sf.importWarnings) resolved["import_warnings"] = sf.importWarnings;
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
  // A failed write (disk full, say) removes what was written before it: a
  // failed run leaves no output file.
  std::vector<std::string> written, extra;
  try {
    writeExr(output, image);
    written.push_back(output);
    writePng(stem + ".png", image);
    written.push_back(stem + ".png");
    writeTextFile(stem + ".config.yaml", std::string(emitter.c_str()) + "\n");
    written.push_back(stem + ".config.yaml");
    extra = integrator->writeExtraOutputs(stem);
  } catch (...) {
    std::error_code ec;
    for (const auto& w : written) std::filesystem::remove(w, ec);
    throw;
  }
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
