#include "experiments/experiment.h"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include "core/scene_loader.h"
#include "experiments/verdict/verdict.h"
#include "integrators/registry.h"

namespace lb {

namespace {

bool integratorUnbiased(const std::string& name, const YAML::Node& params) {
  for (const auto& e : integratorRegistry())
    if (e.name == name) return e.unbiased(params);
  return false;
}

bool integratorExists(const std::string& name) {
  for (const auto& e : integratorRegistry())
    if (e.name == name) return true;
  return false;
}

std::string availableIntegrators() {
  std::string list;
  for (const auto& e : integratorRegistry()) list += (list.empty() ? "" : ", ") + e.name;
  return list;
}

// The mapping minus the keys this file interprets itself. The node itself,
// not a YAML::Clone: a clone loses the marks, and every later error about a
// parameter would point at line 1.
YAML::Node integratorParams(Params& p, const std::string& key) {
  auto child = p.getChild(key);
  if (!child) return YAML::Node(YAML::NodeType::Map);
  return child->node();
}

// Builds the integrator once to check its parameters (unknown keys, ranges).
std::unique_ptr<Integrator> validateIntegrator(const std::string& name, const YAML::Node& params,
                                               const std::string& file, const std::string& context) {
  Params ip(params, file, context);
  return makeIntegrator(name, ip, file, ip.line());
}

// A configuration's `sweep: {key: [values], ...}`: one configuration per
// combination (the cartesian product, keys in the order written), each
// labelled "<label> key=value, ..." and grouped under <label> for the plots.
std::vector<Configuration> expandSweep(Params& cp, const Configuration& base) {
  auto sweep = cp.getChild("sweep");
  if (!sweep) return {base};
  std::vector<std::pair<std::string, YAML::Node>> axes;
  size_t combinations = 1;
  for (auto it = sweep->node().begin(); it != sweep->node().end(); ++it) {
    std::string key = it->first.Scalar();
    YAML::Node values = it->second;
    if (!values.IsSequence() || values.size() == 0)
      sweep->fail(key, "expected a non-empty list of values, e.g. " + key + ": [0.5, 0.7]");
    for (const auto& v : values)
      if (!v.IsScalar()) sweep->fail(key, "sweep values must be single values (numbers, names), got a list or mapping");
    if (base.params[key]) sweep->fail(key, "is also given in params; give it in one place");
    sweep->has(key);  // marks it read
    axes.emplace_back(key, values);
    combinations *= values.size();
    // Each member is a full run per scene and repeat: a typo of a long list
    // would otherwise schedule thousands.
    if (combinations > 256) sweep->fail(key, "the sweep has more than 256 combinations");
  }
  if (axes.empty()) cp.fail("sweep", "expected at least one key: [values]");
  std::vector<Configuration> out;
  for (size_t index = 0; index < combinations; ++index) {
    // Not a copy of `base`: a YAML::Node copy shares its node, and assigning
    // to it would rewrite base's params. A new mapping holding the same value
    // nodes keeps their lines in messages.
    Configuration c;
    c.integrator = base.integrator;
    c.context = base.context;
    c.sampler = base.sampler;
    c.denoise = base.denoise;
    c.adaptive = base.adaptive;
    c.denoiseAt = base.denoiseAt;
    for (auto it = base.params.begin(); it != base.params.end(); ++it) c.params[it->first] = it->second;
    c.sweepGroup = base.label;
    std::string suffix;
    size_t rest = index;
    // The last key varies fastest, as in nested loops written in file order.
    std::vector<size_t> pick(axes.size());
    for (size_t a = axes.size(); a-- > 0;) pick[a] = rest % axes[a].second.size(), rest /= axes[a].second.size();
    for (size_t a = 0; a < axes.size(); ++a) {
      YAML::Node v = axes[a].second[pick[a]];
      c.params[axes[a].first] = v;
      c.sweepValues[axes[a].first] = v;
      suffix += (suffix.empty() ? "" : ", ") + axes[a].first + "=" + v.Scalar();
    }
    c.label = base.label + " " + suffix;
    out.push_back(std::move(c));
  }
  return out;
}

// Params' own file, line and qualified key, as its errors would give them.
KeyLocation locate(const Params& p, const std::string& key) {
  ConfigError where = p.error(key, "");
  return {where.file(), where.key(), where.line()};
}

// "" if `path` exists, else why not: exists() that throws on a path the
// system refuses (a name too long, a loop of links) would end the run with a
// bare filesystem error instead of naming the key (found by fuzz_experiment).
std::string whyMissing(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) return "";
  return ec ? " (" + ec.message() + ")" : "";
}
bool missing(const std::string& path) {
  std::error_code ec;
  return !std::filesystem::exists(path, ec);
}

// The longest scene name, and reference scene file stem (they name a run's
// files and the reference cache's).
constexpr size_t kMaxSceneName = 100;

ReferenceSpec readReference(Params& p, const std::string& folder, const ExperimentOptions& options,
                            KeyLocation* at) {
  ReferenceSpec r;
  *at = locate(p, "reference");
  auto ref = p.getChild("reference");
  if (!ref) {
    if (options.quick) r.spp /= 4;
    return r;
  }
  if (ref->has("file")) {
    *at = locate(*ref, "file");
    r.file = (std::filesystem::path(folder) / ref->getString("file", "")).string();
    if (missing(r.file)) ref->fail("file", "reference image not found: " + r.file + whyMissing(r.file));
    if (ref->has("variance")) {
      r.varianceFile = (std::filesystem::path(folder) / ref->getString("variance", "")).string();
      if (missing(r.varianceFile))
        ref->fail("variance", "reference variance image not found: " + r.varianceFile + whyMissing(r.varianceFile));
      int chunks = ref->getInt("chunks", 0);
      if (chunks != 0 && chunks < 2) ref->fail("chunks", "must be at least 2 (a variance across chunks), or 0: unknown");
      r.chunks = uint64_t(chunks);
    } else if (ref->has("chunks")) {
      ref->fail("chunks", "is the number of chunks of a `variance` image; give `variance` too");
    }
  } else {
    if (ref->has("scene")) {
      *at = locate(*ref, "scene");
      r.scene = (std::filesystem::path(folder) / ref->getString("scene", "")).lexically_normal().string();
      if (missing(r.scene)) ref->fail("scene", "reference scene not found: " + r.scene + whyMissing(r.scene));
      if (std::filesystem::path(r.scene).stem().string().size() > kMaxSceneName)
        ref->fail("scene", "the reference scene's file name is over " + std::to_string(kMaxSceneName) +
                               " bytes: it names the reference's cache files; rename the file");
    }
    r.integrator = ref->getString("integrator", "path");
    if (!integratorExists(r.integrator))
      ref->fail("integrator", "unknown integrator '" + r.integrator + "' (available: " + availableIntegrators() + ")");
    r.params = integratorParams(*ref, "params");
    validateIntegrator(r.integrator, r.params, ref->file(), ref->context() + ".params");
    // A consistent reference carries its own bias into every comparison
    // against it: allowed only when asked for (issue 13).
    bool allowBiased = ref->getBool("allow_biased_reference", false);
    if (!allowBiased && !integratorUnbiased(r.integrator, r.params))
      ref->fail("integrator", "'" + r.integrator + "' with these parameters is not unbiased: its bias would be in the "
                "reference; use path, light, bdpt or vcm with mode: bpt, or say allow_biased_reference: true");
    // One budget: samples, seconds or a noise floor (issue 13).
    int budgets = int(ref->has("spp")) + int(ref->has("seconds")) + int(ref->has("noise_floor"));
    if (budgets > 1)
      ref->fail(ref->has("noise_floor") ? "noise_floor" : "seconds",
                "give one reference budget: spp, seconds or noise_floor");
    if (ref->has("seconds")) {
      double seconds = ref->getFloat("seconds", 0);
      if (!(seconds > 0 && seconds <= kMaxBudgetSeconds)) ref->fail("seconds", "must be > 0 and at most 30 days");
      r.spp = 0;
      r.seconds = options.quick ? seconds / 4 : seconds;
    } else if (ref->has("noise_floor")) {
      double floor = ref->getFloat("noise_floor", 0);
      if (!(floor > 0 && std::isfinite(floor))) ref->fail("noise_floor", "must be > 0 (an RMSE)");
      r.spp = 0;
      r.noiseFloor = options.quick ? floor * 2 : floor;  // a quarter of the work
    } else {
      int spp = ref->getInt("spp", 1024);
      if (spp < 1) ref->fail("spp", "must be at least 1");
      r.spp = options.quick ? std::max(1, spp / 4) : uint64_t(spp);
    }
    int chunk = ref->getInt("chunk_spp", int(r.chunkSpp));
    if (chunk < 1 || chunk > 1 << 20) ref->fail("chunk_spp", "must be between 1 and 1048576");
    r.chunkSpp = uint64_t(chunk);
    // A sample budget makes two chunks at least (their spread is the
    // variance), unless it is a single sample. From the spp as written, not
    // as --quick quarters it: the chunk size is in the cache key, and a quick
    // run should find (and extend) the full run's chunks.
    if (ref->has("spp"))
      r.chunkSpp = std::min<uint64_t>(r.chunkSpp, std::max<uint64_t>(1, uint64_t(ref->getInt("spp", 1)) / 2));
    int seed = ref->getInt("seed", int(r.seed));
    if (seed < 0) ref->fail("seed", "must not be negative");
    r.seed = uint64_t(seed);
  }
  ref->checkUnused();
  return r;
}

// `repeats: N`, or `repeats: {until_decided: true, min: 2, max: 16,
// extend_reference: false}` (verdict/sequential.h).
void readRepeats(Params& p, const ExperimentOptions& options, Experiment& e) {
  if (p.has("repeats") && p.node()["repeats"].IsMap()) {
    std::optional<Params> plan = p.getChild("repeats");
    RepeatPlan& r = e.repeatPlan;
    r.untilDecided = plan->getBool("until_decided", false);
    if (!r.untilDecided)
      plan->fail("until_decided", "a mapping asks for repeats until decided (until_decided: true); a fixed number "
                                  "is written repeats: N");
    r.min = plan->getInt("min", 4);
    r.repeats = plan->getInt("max", 16);
    r.extendReference = plan->getBool("extend_reference", false);
    plan->checkUnused();
    for (const auto& s : e.scenes)
      if (r.extendReference && !s.reference.file.empty())
        plan->fail("extend_reference", "scene '" + s.name + "' has a given reference (file), which cannot be extended");
    if (r.min < 2) plan->fail("min", "must be at least 2 (a pair's test needs two repeats of each)");
    if (r.repeats < r.min || r.repeats > 1000) plan->fail("max", "must be in [min, 1000]");
    e.repeats = r.repeats;
  } else {
    e.repeats = p.getInt("repeats", 1);
    if (e.repeats < 1 || e.repeats > 1000) p.fail("repeats", "must be in [1, 1000]");
    e.repeatPlan.repeats = e.repeats;
  }
  if (options.quick) {
    if (e.repeatPlan.untilDecided)
      warn(p.file() + ":" + std::to_string(p.line("repeats")) + ": --quick runs one repeat, not until decided");
    e.repeats = 1, e.repeatPlan = RepeatPlan{};
  }
}

// rank_by, baseline and confidence: what the verdict ranks by and against.
void readVerdictKeys(Params& p, Experiment& e) {
  std::string metrics;
  for (const auto& m : verdictMetrics()) metrics += (metrics.empty() ? "" : ", ") + m.name;
  e.rankBy = p.getString("rank_by", "relmse");
  auto metric = findVerdictMetric(e.rankBy);
  if (!metric)
    p.fail("rank_by", "unknown metric '" + e.rankBy + "' (a squared error: " + metrics +
                          "; MAPE has no correction for the reference's noise)");
  if (metric->crop)
    for (const auto& s : e.scenes)
      if (s.crop.empty()) p.fail("rank_by", "'" + e.rankBy + "' needs a crop in every scene; scene '" + s.name + "' has none");
  // Read as a float: rounded back to the decimals written (0.95, not 0.949999988).
  e.confidence = std::round(double(p.getFloat("confidence", 0.95f)) * 1e6) / 1e6;
  if (!(e.confidence >= 0.5 && e.confidence <= 0.9999)) p.fail("confidence", "must be in [0.5, 0.9999]");
  if (p.has("baseline")) {
    e.baseline = p.getString("baseline", "");
    std::string labels;
    bool found = false;
    for (const auto& c : e.configurations) {
      labels += (labels.empty() ? "'" : ", '") + c.label + "'";
      found = found || c.label == e.baseline || (!c.denoise.empty() && c.denoisedLabel() == e.baseline);
    }
    if (!found) p.fail("baseline", "no configuration is labelled '" + e.baseline + "' (labels: " + labels + ")");
  }
}

// A run folder names a scene's own files <scene>__<name>.* (the reference's
// images in experiments/runner.cpp, the plots in experiments/report/plots.py)
// and a configuration's <scene>__<slug(label)>.*: a label whose slug is one
// of these names, or starts a sweep plot's, would replace that file (issue
// 34: a configuration labelled "reference" overwrote the reference).
// tests/experiments/runner_test.cpp checks the list against what a run writes.
constexpr const char* kRunFileNames[] = {"reference", "convergence", "efficiency"};
constexpr const char* kSweepPlotPrefix = "sweep-";
// The longest a configuration's file adds to <scene>__<slug>: "__repeat1000.exr"
// (repeats are at most 1000; longer than "_error_crop.png"), and each file is
// first written as .<name>.tmp-<pid> (core/image.cpp; Linux's pids have at
// most 7 digits).
constexpr size_t kLongestSuffix = sizeof("__repeat1000.exr") - 1 + sizeof("..tmp-4194304") - 1;
constexpr size_t kNameMax = 255;  // NAME_MAX of Linux's file systems

// Why `label` cannot name a configuration's files in these scenes' run
// folder, or "" if it can: checked before anything renders, so a label does
// not fail a run at its first image, after the reference was cached.
std::string runFileProblem(const std::string& label, const std::vector<ExperimentScene>& scenes) {
  std::string s = slug(label);
  if (s.empty()) return "a label must not be empty (it names the configuration's files)";
  for (const char* name : kRunFileNames)
    if (s == name)
      return "label '" + label + "' would name its files <scene>__" + name +
             ".*, which the run writes itself; choose another label";
  if (s.rfind(kSweepPlotPrefix, 0) == 0)
    return "label '" + label + "' would name its files like a sweep's plot (<scene>__" + kSweepPlotPrefix +
           "*); choose another label";
  size_t longestScene = 0;
  for (const auto& scene : scenes) longestScene = std::max(longestScene, scene.name.size());
  size_t fixed = longestScene + 2 + kLongestSuffix;
  if (fixed + s.size() > kNameMax)
    return "label '" + label.substr(0, 24) + "…' is " + std::to_string(label.size()) +
           " bytes: its files would have names of " + std::to_string(fixed + s.size()) +
           " bytes, over the file system's " + std::to_string(kNameMax) + "; with these scene names a label has at most " +
           std::to_string(fixed < kNameMax ? kNameMax - fixed : 0) + " bytes";
  return "";
}

}  // namespace

std::string slug(const std::string& label) {
  std::string out;
  for (char c : label) out += std::isalnum(static_cast<unsigned char>(c)) ? char(std::tolower(c)) : '-';
  return out;
}

std::string flowYaml(const YAML::Node& node) {
  YAML::Emitter e;
  e << YAML::Flow << node;
  return e.c_str();
}

Experiment loadExperiment(const std::string& path, const ExperimentOptions& options) {
  Experiment e;
  e.file = path;
  e.source = loadYamlFile(path);
  Params p(e.source, path, "");
  std::string folder = std::filesystem::path(path).parent_path().string();
  e.name = p.getString("name", std::filesystem::path(path).stem().string());
  // The run folder is <results>/<name>/: a path here would put it elsewhere.
  // Control characters (a newline) make folder names no shell or CSV reader
  // handles; 200 bytes leave room for the run id under NAME_MAX (255).
  bool control = std::any_of(e.name.begin(), e.name.end(), [](char c) { return (unsigned char)c < 0x20 || c == 0x7f; });
  if (e.name.empty() || e.name == "." || e.name == ".." || e.name.find_first_of("/\\") != std::string::npos ||
      control || e.name.size() > 200)
    p.fail("name", "must be a plain folder name (not empty, at most 200 bytes, no '/' or control characters, not '.' "
                   "or '..'), got '" + (control ? std::string("(a name with control characters)") : e.name.substr(0, 60)) + "'");

  for (Params& sp : p.getList("scenes")) {
    ExperimentScene s;
    s.path = (std::filesystem::path(folder) / sp.requireString("scene")).lexically_normal().string();
    if (missing(s.path)) sp.fail("scene", "scene file not found: " + s.path + whyMissing(s.path));
    s.sceneAt = locate(sp, "scene");
    if (sp.has("name")) {
      s.name = sp.getString("name", "");
      if (s.name.empty() || s.name.find_first_of("/\\ ") != std::string::npos)
        sp.fail("name", "must be a non-empty file-name stem (no spaces or slashes)");
    } else {
      // Derived from the file name, which may hold spaces ("my scene.yaml" → my-scene).
      s.name = std::filesystem::path(s.path).stem().string();
      std::replace_if(s.name.begin(), s.name.end(), [](char c) { return c == ' ' || c == '\\'; }, '-');
      if (s.name.empty()) sp.fail("scene", "the file name has no stem to name the scene by: give it a `name`");
    }
    // Its files are <name>__<label>... and its reference's cache
    // <name>-<key>.variance.exr: 100 bytes leave room for both under NAME_MAX,
    // so a long name is refused here, not blamed on a label or found after
    // the reference's first chunk (issue 34, class 6).
    if (s.name.size() > kMaxSceneName)
      sp.fail(sp.has("name") ? "name" : "scene", "the scene's name '" + s.name.substr(0, 24) + "…' is " +
                                                     std::to_string(s.name.size()) + " bytes; at most " +
                                                     std::to_string(kMaxSceneName) + " (it names the run's files)" +
                                                     (sp.has("name") ? "" : ": give a shorter `name`"));
    // "__" separates a scene's name from a label in file names: scene cb's
    // configuration x_repeat1 and a scene cb__x's would share them.
    if (s.name.find("__") != std::string::npos)
      sp.fail(sp.has("name") ? "name" : "scene", "the scene's name '" + s.name.substr(0, 40) +
                                                     "' holds \"__\", which separates scene and label in the run's file "
                                                     "names" + (sp.has("name") ? "" : ": give a `name`"));
    for (const auto& other : e.scenes)
      if (other.name == s.name) sp.fail(sp.has("name") ? "name" : "scene", "two scenes are named '" + s.name + "': give one a `name`");
    if (sp.has("world_scale")) {  // the run's scene scaled (camera, lights and radii too)
      float scale = sp.getFloat("world_scale", 1);
      if (std::string problem = worldScaleProblem(scale); !problem.empty()) sp.fail("world_scale", problem);
      s.overrides["world_scale"] = scale;
    }
    if (sp.has("resolution")) {
      YAML::Node res = sp.node()["resolution"];
      if (!res.IsSequence() || res.size() != 2) sp.fail("resolution", "expected [width, height]");
      int w = 0, h = 0;
      try {
        w = res[0].as<int>(), h = res[1].as<int>();
      } catch (const YAML::Exception&) {
        sp.fail("resolution", "expected two integers");
      }
      if (w <= 0 || h <= 0 || w > 8192 || h > 8192)
        sp.fail("resolution", "each must be from 1 to 8192 (the largest image the run's readers read, as --resolution)");
      std::string problem = filmMemoryProblem(w, h);
      if (!problem.empty()) sp.fail("resolution", problem);
      s.overrides["film"]["width"] = w;
      s.overrides["film"]["height"] = h;
      s.resolution["film"]["width"] = w;
      s.resolution["film"]["height"] = h;
    }
    s.reference = readReference(sp, folder, options, &s.referenceAt);
    s.cropAt = locate(sp, "crop");
    if (sp.has("crop")) {
      YAML::Node c = sp.node()["crop"];
      if (!c.IsSequence() || c.size() != 4) sp.fail("crop", "expected [x0, y0, x1, y1] in pixels");
      try {
        s.crop = {c[0].as<int>(), c[1].as<int>(), c[2].as<int>(), c[3].as<int>()};
      } catch (const YAML::Exception&) {
        sp.fail("crop", "expected four integers");
      }
      if (s.crop.x0 < 0 || s.crop.y0 < 0) sp.fail("crop", "x0 and y0 must not be negative (pixels from the top left)");
      if (s.crop.empty()) sp.fail("crop", "must be a non-empty region (x0 < x1, y0 < y1)");
    }
    sp.checkUnused();
    e.scenes.push_back(std::move(s));
  }
  if (e.scenes.empty()) p.fail("scenes", "at least one scene is required");

  std::vector<Params> configs = p.getList("configurations");
  if (configs.empty()) p.fail("configurations", "at least one configuration is required");
  for (Params& cp : configs) {
    Configuration base;
    base.integrator = cp.requireString("integrator");
    base.label = cp.getString("label", base.integrator);
    base.params = integratorParams(cp, "params");
    base.context = cp.context() + ".params";
    if (auto s = cp.getChild("sampler")) base.sampler = readSamplerSettings(*s);
    if (auto a = cp.getChild("adaptive")) base.adaptive = AdaptiveSettings::read(*a);
    base.denoise = cp.getString("denoise", "");
    base.denoiseAt = {cp.file(), cp.context() + ".denoise", cp.line("denoise")};
    if (!base.denoise.empty() && base.denoise != "nlmeans")
      cp.fail("denoise", "unknown denoiser '" + base.denoise +
                             "' (available: nlmeans, the feature-guided non-local means of Rousselle et al. 2013)");
    std::vector<Configuration> members = expandSweep(cp, base);
    cp.checkUnused();
    if (!integratorExists(base.integrator)) {
      std::string msg = "integrator '" + base.integrator + "' is not built (available: " + availableIntegrators() + ")";
      if (!options.quick) cp.fail("integrator", msg);
      warn(cp.file() + ":" + std::to_string(cp.line("integrator")) + ": " + msg + "; skipped under --quick");
      continue;
    }
    for (Configuration& c : members) {
      for (const auto& other : e.configurations)
        if (slug(other.label) == slug(c.label) || (!other.denoise.empty() && slug(other.denoisedLabel()) == slug(c.label)) ||
            (!c.denoise.empty() && slug(c.denoisedLabel()) == slug(other.label)))
          cp.fail(c.sweepGroup.empty() ? "label" : "sweep", "label '" + c.label + "' collides with '" + other.label +
                                                                "' (file names use letters and digits, lower case)");
      for (const std::string& label : {c.label, c.denoise.empty() ? c.label : c.denoisedLabel()})
        if (std::string problem = runFileProblem(label, e.scenes); !problem.empty())
          cp.fail(c.sweepGroup.empty() ? "label" : "sweep", problem);
      auto integrator =
          validateIntegrator(c.integrator, c.params, cp.file(), c.sweepGroup.empty() ? c.context : cp.context() + ".sweep");
      if (c.adaptive.enabled && !integrator->adaptiveRefusal().empty())
        cp.fail("adaptive", "adaptive sampling cannot drive '" + c.integrator + "': " + integrator->adaptiveRefusal());
      if (!c.denoise.empty() && !integrator->independentPasses())
        cp.fail("denoise", "'" + c.integrator + "' has correlated passes, so its film has no per-pixel variance, "
                           "which the filter measures colour differences in; remove denoise");
      e.configurations.push_back(std::move(c));
    }
  }
  if (e.configurations.empty()) p.fail("configurations", "no configuration can run");

  auto budget = p.getChild("budget");
  if (!budget) p.fail("budget", "is required (seconds and/or spp)");
  e.budget.seconds = budget->getFloat("seconds", 0);
  int spp = budget->getInt("spp", 0);
  budget->checkUnused();
  if (!(e.budget.seconds >= 0 && e.budget.seconds <= kMaxBudgetSeconds))
    budget->fail("seconds", "must be in [0, 30 days] (2592000 s)");
  if (spp < 0) budget->fail("spp", "must not be negative");
  e.budget.spp = uint64_t(spp);
  if (e.budget.seconds == 0 && e.budget.spp == 0) p.fail("budget", "needs seconds > 0 and/or spp > 0");
  // An adaptive configuration whose budget ends within its uniform passes
  // adapts nothing: it would be compared as adaptive while it was not (issue
  // 34, class 7; `render --adaptive` says so after the render).
  for (const Configuration& c : e.configurations)
    if (c.adaptive.enabled && e.budget.spp != 0 && e.budget.spp <= uint64_t(c.adaptive.passes))
      budget->fail("spp", std::to_string(e.budget.spp) + " samples per pixel end within configuration '" + c.label +
                              "''s " + std::to_string(c.adaptive.passes) +
                              " uniform passes (adaptive.passes): nothing would adapt; raise spp or lower passes");
  if (options.quick) e.budget.seconds /= 4, e.budget.spp = e.budget.spp ? std::max<uint64_t>(1, e.budget.spp / 4) : 0;

  if (auto snaps = p.getChild("snapshots")) {
    e.snapshots = snaps->getInt("count", 8);
    if (e.snapshots < 1 || e.snapshots > 1000) snaps->fail("count", "must be in [1, 1000]");
    e.spacing = snaps->getChoice("spacing", "log", {"log", "linear"}) == "log" ? SnapshotSpacing::Log
                                                                              : SnapshotSpacing::Linear;
    snaps->checkUnused();
  }
  if (p.has("metrics")) {
    YAML::Node m = p.node()["metrics"];
    const std::string names = "rmse, relmse, relmse_trimmed, mape, variance";
    if (!m.IsSequence()) p.fail("metrics", "expected a list, e.g. [rmse, relmse]");
    e.metrics.clear();
    for (const auto& item : m) {
      if (!item.IsScalar()) p.fail("metrics", "each metric is a name (" + names + "), not a list or mapping");
      std::string name = item.Scalar();
      if (name != "rmse" && name != "relmse" && name != "relmse_trimmed" && name != "mape" && name != "variance")
        p.fail("metrics", "unknown metric '" + name + "' (expected " + names + ")");
      e.metrics.push_back(name);
    }
  }
  readRepeats(p, options, e);
  int seed = p.getInt("seed", 1);
  if (seed < 0) p.fail("seed", "must not be negative");  // meta.json said -1, log.csv 2^64 - 1
  e.seed = uint64_t(seed);
  e.metricSettings.relEpsilon = p.getFloat("relmse_epsilon", 1e-2f);
  if (!(e.metricSettings.relEpsilon > 0)) p.fail("relmse_epsilon", "must be positive");
  if (p.has("outlier_percentile"))
    p.fail("outlier_percentile", "was replaced by the relmse_trimmed metric (trim_fraction: the share of pixels "
                                 "it rejects, default 0.001)");
  e.metricSettings.trimFraction = p.getFloat("trim_fraction", 1e-3f);
  if (!(e.metricSettings.trimFraction >= 0 && e.metricSettings.trimFraction < 0.5f))
    p.fail("trim_fraction", "must be in [0, 0.5): the share of pixels relmse_trimmed rejects");
  readVerdictKeys(p, e);
  p.checkUnused();
  return e;
}

}  // namespace lb
