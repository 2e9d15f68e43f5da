// `lightbench render`: load, render within a budget, write EXR + PNG + resolved
// configuration, print a summary. Output files appear only after a complete
// render, each through a temporary name and a rename.
#include <tbb/global_control.h>
#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include "core/aov.h"
#include "core/format.h"
#include "core/scene_import.h"
#include "core/scene_loader.h"
#include "experiments/chunks.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/experiment.h"
#include "experiments/meta.h"
#include "experiments/reference.h"
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
  // Keys that define the integral (an imported scene's max_depth) hold for
  // every integrator that reads them.
  c.params = withSharedIntegratorKeys(sf, c.params, keysReadBy(c.name));
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

// `lightbench render experiment.yaml`: say which command was meant instead of
// reporting the experiment's keys as unknown scene keys.
void checkNotAnExperiment(const std::string& path) {
  if (isImportedScenePath(path)) return;
  YAML::Node root = loadYamlFile(path);
  if (root.IsMap() && root["configurations"] && !root["camera"])
    throw ConfigError(path, root["configurations"].Mark().line + 1, "configurations",
                      "this is an experiment, not a scene: run it with 'lightbench run " + path + "'");
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
  for (const std::string& path : {output, stem + ".png", stem + ".config.yaml"}) {
    checkFileNameFits("--output", path);
    if (fs::is_directory(path, ec)) throw flagError("--output", "cannot write " + path + ": it is a directory");
  }
}

void printSummary(const RenderedImage& r) {
  const RenderReport& rep = r.report;
  std::cerr << "done: " << formatSeconds(rep.seconds) << " (preprocess " << formatSeconds(rep.preprocessSeconds)
            << "), " << rep.passes << " spp, "
            << formatCount(double(rep.rays) / std::max(rep.seconds - rep.preprocessSeconds, 1e-9), "rays/s")
            << ", NaN/Inf samples: " << rep.nonFinite << "\n";
  // A budget shorter than the preprocess still renders one pass: say so, or
  // an equal-time comparison would silently be unequal.
  std::string over = overBudgetMessage(rep);
  if (!over.empty()) std::cerr << "warning: " << over << "\n";
  for (const std::string& line : r.integratorSummary) std::cerr << line << "\n";
  for (const auto& s : r.firstNonFinite)
    std::cerr << "  non-finite sample: --pixel " << s.x << "," << s.y << " --sample " << s.sampleIndex << "\n";
}

// What every render needs before it starts: the scene, the integrator with
// its parameters read (bad input found here, before any work).
struct Prepared {
  SceneFile sf;
  IntegratorChoice choice;
  Params params;
  std::unique_ptr<Integrator> integrator;
  // Owned here, not by the render: an integrator may keep a pointer to it for
  // its extra outputs (the irradiance cache's record image), written later.
  std::unique_ptr<Film> film;
};

Prepared prepare(const RenderArgs& args) {
  if (!args.integrator.empty()) checkIntegratorName(args.integrator);
  YAML::Node sceneOverrides(YAML::NodeType::Map);
  if (args.worldScale > 0) {
    if (std::string problem = worldScaleProblem(args.worldScale); !problem.empty()) throw flagError("--world-scale", problem);
    sceneOverrides["world_scale"] = args.worldScale;
  }
  if (!args.resolution.empty()) {
    int w = 0, h = 0;
    if (!parseResolution(args.resolution, w, h))
      throw flagError("--resolution", "must be WIDTHxHEIGHT, got '" + args.resolution + "'");
    sceneOverrides["film"]["width"] = w;
    sceneOverrides["film"]["height"] = h;
  }
  checkNotAnExperiment(args.scene);
  SceneLoadOptions loadOptions;
  loadOptions.strict = args.strict;
  loadOptions.deferWarnings = true;  // printed once the flags, integrator and outputs are accepted too (runRender)
  SceneFile sf = loadScene(args.scene, sceneOverrides, loadOptions);
  if (!args.sampler.empty()) sf.sampler.type = args.sampler;
  if (!args.crop.empty()) {
    int w[4];
    Camera& cam = sf.scene->camera;
    if (!parseCrop(args.crop, w)) throw flagError("--crop", "must be X0,Y0,X1,Y1, got '" + args.crop + "'");
    if (w[2] > cam.width() || w[3] > cam.height())
      throw flagError("--crop", "the window " + args.crop + " is not inside the " + std::to_string(cam.width()) + "x" +
                                    std::to_string(cam.height()) + " film");
    cam.crop(w[0], w[1], w[2], w[3]);
  }
  IntegratorChoice choice = chooseIntegrator(sf, args);
  Params params(choice.params, args.scene, "integrator");
  for (const auto& k : choice.overridden) params.markOverridden(k);
  auto integrator = makeIntegrator(choice.name, params, args.scene, choice.line);
  if (args.adaptive && !integrator->adaptiveRefusal().empty())
    throw flagError("--adaptive", choice.name + ": " + integrator->adaptiveRefusal());
  if (!integrator->independentPasses() && std::find(args.aovs.begin(), args.aovs.end(), "variance") != args.aovs.end())
    throw flagError("--aov", "variance: " + choice.name +
                                 "'s passes are correlated (Markov chains), so their spread is no error estimate; "
                                 "use independent runs (seeds)");
  return {std::move(sf), std::move(choice), std::move(params), std::move(integrator), nullptr};
}

// The AOV layers asked for, in the order of aovNames().
std::vector<ExrLayer> aovLayers(const std::vector<std::string>& wanted, const Scene& scene, const Film& film,
                                uint64_t seed) {
  auto asked = [&](const std::string& n) { return std::find(wanted.begin(), wanted.end(), n) != wanted.end(); };
  std::vector<ExrLayer> layers;
  if (asked("albedo") || asked("normal") || asked("depth")) {
    // 16 jittered rays a pixel: antialiased edges, and the albedo's BSDF-sampled estimate settles.
    FirstHitImages first = renderFirstHitImages(scene, 16, seed);
    if (asked("albedo")) layers.push_back({"albedo", {"R", "G", "B"}, std::move(first.albedo)});
    if (asked("normal")) layers.push_back({"normal", {"X", "Y", "Z"}, std::move(first.normal)});
    if (asked("depth")) layers.push_back({"depth", {"Z"}, std::move(first.depth)});
  }
  if (asked("variance")) {
    size_t overflowed = 0;
    layers.push_back({"variance", {"R", "G", "B"}, film.varianceOfMean(&overflowed)});
    if (overflowed)
      std::cerr << "warning: the variance layer is beyond a float's range in " << overflowed
                << " pixel(s), written as the largest float (3.4e38)\n";
  }
  if (asked("spp")) {
    Image count(film.width(), film.height());
    for (int y = 0; y < film.height(); ++y)
      for (int x = 0; x < film.width(); ++x)
        // Camera samples where the integrator adds them per pixel; else each pass is one estimate per pixel.
        count.at(x, y) = Color(float(film.samples(x, y) ? film.samples(x, y) : film.passes()));
    layers.push_back({"spp", {"Y"}, std::move(count)});
  }
  return layers;
}

// An integrator as prepare() made it, anew: each chunk of a distributed
// render starts from scratch.
std::unique_ptr<Integrator> freshIntegrator(const Prepared& job, const RenderArgs& args) {
  Params params(job.choice.params, args.scene, "integrator");
  for (const auto& k : job.choice.overridden) params.markOverridden(k);
  return makeIntegrator(job.choice.name, params, args.scene, job.choice.line);
}

// What every rank of a distributed render must share: the scene file's
// bytes, the flags that change the image, the rendering code and the build.
std::string renderIdentity(const RenderArgs& args) {
  std::vector<std::string> parts = {fileBytes(args.scene), renderSourceHash(), LIGHTBENCH_GIT, args.integrator,
                                    args.resolution, args.crop, args.sampler, std::to_string(args.worldScale),
                                    std::to_string(args.seed), std::to_string(args.spp),
                                    std::to_string(args.chunkSpp)};
  parts.insert(parts.end(), args.overrides.begin(), args.overrides.end());
  return hashStrings(parts);
}

// --distributed's limits, checked before anything renders.
void checkDistributed(const Prepared& job, const RenderArgs& args) {
  if (!args.distributed) return;
  if (args.seconds > 0) throw flagError("--distributed", "needs --spp: a time budget cannot be split the same way on any number of ranks");
  if (!args.aovs.empty()) throw flagError("--aov", "not with --distributed (the layers would need their own chunks)");
  if (args.adaptive) throw flagError("--adaptive", "not with --distributed (adaptive passes depend on earlier ones)");
  std::string why = job.integrator->splitRefusal();
  if (!why.empty()) throw flagError("--distributed", job.choice.name + " cannot be split into chunks exactly: " + why);
  uint64_t spp = args.spp ? args.spp : (job.sf.sceneSpp ? job.sf.sceneSpp : 16);
  if (spp % args.chunkSpp != 0)
    throw flagError("--chunk-spp", std::to_string(args.chunkSpp) + " does not divide the " + std::to_string(spp) +
                                       " spp: every chunk must have the same number of passes");
}

RenderedImage renderPrepared(Prepared& job, const RenderArgs& args) {
  RenderOptions options;
  options.seed = args.seed;
  options.budget.spp = args.spp;
  options.budget.seconds = args.seconds;
  if (options.budget.spp == 0 && options.budget.seconds == 0) options.budget.spp = job.sf.sceneSpp ? job.sf.sceneSpp : 16;
  options.progress = !args.quiet;
  options.adaptive.enabled = args.adaptive;
  options.adaptive.passes = args.adaptivePasses;
  options.adaptive.targetRelativeError = args.adaptiveTarget;

  const Camera& cam = job.sf.scene->camera;
  job.film = std::make_unique<Film>(cam.width(), cam.height());
  const Film& film = *job.film;
  RenderReport rep;
  Image chunkMean;
  if (args.distributed) {
    ChunkedRender c = renderChunked(*job.sf.scene, job.sf.sampler, [&] { return freshIntegrator(job, args); },
                                    args.seed, options.budget.spp, args.chunkSpp, args.farm, renderIdentity(args),
                                    options.progress);
    chunkMean = std::move(c.mean);
    rep.passes = c.passes, rep.seconds = c.seconds, rep.nonFinite = c.nonFinite, rep.rays = c.rays;
  } else {
    std::function<void(const PassProgress&)> afterPass;
    if (args.betweenPasses) afterPass = [&](const PassProgress&) { args.betweenPasses(); };
    rep = renderLoop(*job.sf.scene, *job.integrator, *job.film, job.sf.sampler, options, afterPass);
  }

  YAML::Node resolved;
  resolved["lightbench"] = versionString();
  resolved["scene_file"] = args.scene;
  resolved["scene"] = job.sf.description;
  // What the command line changed: the scene above is the file as written.
  const Camera& camera = job.sf.scene->camera;
  if (!args.resolution.empty()) resolved["resolution"] = args.resolution;
  if (!args.crop.empty()) resolved["crop"] = args.crop;
  if (args.worldScale > 0) resolved["world_scale"] = args.worldScale;
  resolved["image_size"] = std::to_string(camera.width()) + "x" + std::to_string(camera.height());
  if (job.sf.importWarnings) resolved["import_warnings"] = job.sf.importWarnings;
  YAML::Node integ = YAML::Clone(job.params.resolved());  // a clone: adding `name` must not write into Params
  integ["name"] = job.choice.name;
  resolved["integrator"] = integ;
  resolved["sampler"]["type"] = job.sf.sampler.type;
  resolved["sampler"]["strata"] = job.sf.sampler.strata;
  resolved["sampler"]["spp"] = job.sf.sampler.spp;
  resolved["seed"] = args.seed;
  resolved["spp"] = rep.passes;
  resolved["threads"] = args.threads;
  resolved["seconds"] = rep.seconds;
  if (args.distributed) {
    resolved["distributed"]["chunk_spp"] = args.chunkSpp;
    resolved["distributed"]["ranks"] = args.farm ? args.farm->cluster().size() : 1;
  }
  if (args.adaptive) {
    resolved["adaptive"]["passes"] = args.adaptivePasses;
    resolved["adaptive"]["target_relative_error"] = args.adaptiveTarget;
    resolved["adaptive"]["converged"] = rep.converged;
    // The first --adaptive-passes passes are uniform: a budget that ends
    // within them rendered a plain image, which must not pass for an adaptive one.
    const bool adapted = rep.passes > uint64_t(args.adaptivePasses);
    resolved["adaptive"]["adapted"] = adapted;
    if (!adapted)
      warn("--adaptive: the render ended after " + std::to_string(rep.passes) + " pass(es), within its " +
           std::to_string(args.adaptivePasses) + " uniform ones (--adaptive-passes): nothing adapted");
  }
  if (rep.budgetSeconds > 0) resolved["over_budget_seconds"] = rep.overBudgetSeconds();
  resolved["non_finite_samples"] = rep.nonFinite;
  std::vector<std::string> integratorSummary = job.integrator->summaryLines();
  for (const std::string& line : integratorSummary) resolved["integrator_summary"].push_back(line);
  YAML::Emitter emitter;
  emitter << resolved;
  RenderedImage out{args.distributed ? chunkMean : film.image(), resolved, std::string(emitter.c_str()) + "\n", rep, film.firstNonFinite(), {}, {}, {}};
  out.integratorSummary = std::move(integratorSummary);
  out.layers = aovLayers(args.aovs, *job.sf.scene, film, args.seed);
  if (!args.distributed)  // the chunks' integrators are gone; job.integrator rendered nothing
    for (ExrLayer& layer : job.integrator->extraLayers()) out.layers.push_back(std::move(layer));
  // The EXR carries what made it: a file copied away from its .config.yaml still says.
  out.attributes = {{"lightbench/version", versionString()},
                    {"lightbench/scene", args.scene},
                    {"lightbench/integrator", job.choice.name},
                    {"lightbench/parameters", flowYaml(integ)},
                    {"lightbench/spp", std::to_string(rep.passes)},
                    {"lightbench/seconds", std::to_string(rep.seconds)},
                    {"lightbench/seed", std::to_string(args.seed)},
                    {"lightbench/non_finite_samples", std::to_string(rep.nonFinite)}};
  if (!args.resolution.empty()) out.attributes["lightbench/resolution"] = args.resolution;
  if (!args.crop.empty()) out.attributes["lightbench/crop"] = args.crop;
  return out;
}

std::unique_ptr<tbb::global_control> limitThreads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));
}

int render(const RenderArgs& args) {
  const bool replay = !args.replayPixel.empty() || args.replaySample >= 0;
  if (!args.aovs.empty() && std::filesystem::path(args.output).extension() == ".png")
    throw flagError("--aov", "AOVs are layers of the EXR; -o " + args.output + " writes the PNG preview only");
  if (!args.replayPixel.empty() && args.replaySample < 0) throw flagError("--sample", "--pixel needs --sample I");
  if (args.replayPixel.empty() && args.replaySample >= 0) throw flagError("--pixel", "--sample needs --pixel X,Y");
  if (!args.integrator.empty()) checkIntegratorName(args.integrator);
  std::string output = args.output.empty() ? std::filesystem::path(args.scene).stem().string() + ".exr" : args.output;
  if (!replay) checkOutputs(output);

  Prepared job = prepare(args);
  if (args.distributed && replay) throw flagError("--distributed", "not with --pixel/--sample");
  checkDistributed(job, args);
  if (args.farm && !args.distributed)
    std::cerr << "note: rank 0 renders alone; --distributed splits a render over the MPI ranks\n";
  if (!replay)
    for (const std::string& path : job.integrator->extraOutputPaths(stemPath(output))) {
      std::error_code ec;
      checkFileNameFits("--output", path);
      if (std::filesystem::is_directory(path, ec)) throw flagError("--output", "cannot write " + path + ": it is a directory");
    }
  printSceneWarnings(job.sf);
  auto threads = limitThreads(args.threads);

  if (replay) {
    if (!job.integrator->replaysSamples())
      throw flagError("--pixel", "integrator '" + job.choice.name +
                                     "' cannot replay single samples: its camera samples are not each estimated on their own (it merges paths, or learns from earlier passes)");
    const Camera& cam = job.sf.scene->camera;
    int x = -1, y = -1;
    if (!parsePixel(args.replayPixel, x, y) || x >= cam.width() || y >= cam.height())
      throw flagError("--pixel", "must be a pixel X,Y inside the " + std::to_string(cam.width()) + "x" +
                                     std::to_string(cam.height()) + " film, got '" + args.replayPixel + "'");
    enableFlushToZeroOnAllThreads();
    auto sampler = makeSampler(job.sf.sampler, args.seed, job.sf.scene->camera.width(), job.sf.scene->camera.height());
    job.integrator->preprocess(*job.sf.scene, *sampler);
    auto value = job.integrator->replaySample(*job.sf.scene, *sampler, x, y, uint64_t(args.replaySample));
    if (!value) {
      std::cerr << "error: integrator '" << job.choice.name << "' cannot replay single samples\n";
      return 1;
    }
    std::cout << "pixel " << x << "," << y << " sample " << args.replaySample << ": " << value->r << " " << value->g
              << " " << value->b << "\n";
    return 0;
  }

  RenderedImage rendered = renderPrepared(job, args);
  const Image& image = rendered.image;
  std::string stem = stemPath(output);
  // -o NAME.png: the preview only, and said so (an EXR is never written under
  // a .png name, nor a PNG over an EXR).
  const bool pngOnly = std::filesystem::path(output).extension() == ".png";
  // A failed write (disk full, say) removes what was written before it: a
  // failed run leaves no output file.
  std::vector<std::string> written, extra;
  try {
    if (!pngOnly) {
      writeExr(output, image, rendered.layers, rendered.attributes);
      written.push_back(output);
    }
    writePng(stem + ".png", image, args.exposure);
    written.push_back(stem + ".png");
    writeTextFile(stem + ".config.yaml", rendered.resolvedYaml);
    written.push_back(stem + ".config.yaml");
    if (!args.distributed) extra = job.integrator->writeExtraOutputs(stem);
  } catch (...) {
    std::error_code ec;
    for (const auto& w : written) std::filesystem::remove(w, ec);
    throw;
  }
  printSummary(rendered);
  if (pngOnly)
    std::cerr << "wrote " << stem << ".png (the 8-bit preview only: -o NAME.exr keeps the float image"
              << (rendered.layers.empty() ? "" : " and its layers") << ") and " << stem << ".config.yaml";
  else
    std::cerr << "wrote " << output << (rendered.layers.empty() ? "" : " (" + std::to_string(rendered.layers.size()) + " layers)")
              << ", " << stem << ".png, " << stem << ".config.yaml";
  if (!extra.empty()) std::cerr << " and " << extra.size() << " more (" << extra.front() << " …)";
  std::cerr << "\n";
  return 0;
}

}  // namespace

const std::vector<std::string>& aovNames() {
  static const std::vector<std::string> names = {"albedo", "normal", "depth", "variance", "spp"};
  return names;
}

RenderedImage renderToMemory(const RenderArgs& args) {
  Prepared job = prepare(args);
  printSceneWarnings(job.sf);
  auto threads = limitThreads(args.threads);
  return renderPrepared(job, args);
}

int runRender(const RenderArgs& args) {
  return withErrorExitCodes([&] { return render(args); });
}

int serveRender(const RenderArgs& args) {
  return withErrorExitCodes([&] {
    // Prepared at the first task, which comes only after rank 0's checks passed.
    std::optional<Prepared> job;
    std::string identity;
    auto threads = limitThreads(workerThreads(args.threads, args.farm->cluster()));
    return args.farm->serve([&](const std::string& task) {
      if (!job) job.emplace(prepare(args)), identity = renderIdentity(args);
      ByteReader r(task);
      if (r.str() != identity)
        throw ConfigError(args.scene, 0, "", "this rank (" + hostName() + ") reads another scene or runs another "
                          "lightbench build than rank 0; every rank must see the same files and run the same build");
      uint64_t k = r.u64();
      auto integrator = freshIntegrator(*job, args);
      return chunkResult(k, renderChunk(*job->sf.scene, *integrator, job->sf.sampler, args.seed, k, args.chunkSpp));
    });
  });
}

}  // namespace lb
