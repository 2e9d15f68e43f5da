#include "experiments/reference.h"
#include "core/format.h"
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <iomanip>
#include <iostream>
#include <sstream>
#include "core/scene_loader.h"
#include "experiments/chunks.h"
#include "experiments/run_lock.h"
#include "render_source_hash.h"
#include "integrators/registry.h"

namespace lb {

namespace {
struct Fnv1a {
  uint64_t h = 0xcbf29ce484222325ULL;
  void add(const std::string& bytes) {
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ULL;
    h = (h ^ 0xff) * 0x100000001b3ULL;  // separator, so "ab"+"c" differs from "a"+"bc"
  }
  std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", (unsigned long long)h);
    return out;
  }
};
std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

std::string renderSourceHash() { return LIGHTBENCH_RENDER_SOURCE_HASH; }

std::string integratorSourceHash(const std::string& name) {
  static const std::map<std::string, std::string> table = LIGHTBENCH_INTEGRATOR_SOURCE_HASHES;
  auto it = table.find(name);
  return it == table.end() ? renderSourceHash() : it->second;
}
std::string fileBytes(const std::string& path) { return readBytes(path); }

std::string hashStrings(const std::vector<std::string>& parts) {
  Fnv1a f;
  for (const auto& p : parts) f.add(p);
  return f.hex();
}

namespace {
// The scene a reference is rendered from, and its overrides.
const std::string& referenceScene(const ExperimentScene& s) { return s.reference.scene.empty() ? s.path : s.reference.scene; }
const YAML::Node& referenceOverrides(const ExperimentScene& s) {
  return s.reference.scene.empty() ? s.overrides : s.resolution;
}
// Cached references are named after the scene they are rendered from, so
// runs sharing one (a scale sweep against the unscaled scene) share the file.
std::string referenceName(const ExperimentScene& s) {
  return s.reference.scene.empty() ? s.name : std::filesystem::path(s.reference.scene).stem().string();
}
}  // namespace

std::string referenceKey(const ExperimentScene& s) {
  Fnv1a f;
  // The hash of the code the reference's integrator compiles from (cmake/
  // render_source_hash.cmake): a fixed integrator must not keep serving
  // references computed before the fix, but a commit that changes only
  // another integrator, the experiments or the docs keeps a long reference
  // usable (v3: keyed per integrator since issue 39).
  f.add("lightbench-reference-v3 " + integratorSourceHash(s.reference.integrator));
  const std::string& scene = referenceScene(s);
  f.add(readBytes(scene));
  YAML::Node root = loadSceneDescription(scene);
  std::string folder = std::filesystem::path(scene).parent_path().string();
  // Every file the scene reads: meshes, environment maps, textures.
  auto addFile = [&](const YAML::Node& n) {
    if (n.IsMap() && n["file"] && n["file"].IsScalar())
      f.add(readBytes((std::filesystem::path(folder) / n["file"].as<std::string>()).string()));
  };
  for (const char* list : {"shapes", "lights"})
    if (root[list] && root[list].IsSequence())
      for (const auto& item : root[list]) addFile(item);
  if (root["materials"] && root["materials"].IsMap())
    for (const auto& m : root["materials"])
      if (m.second.IsMap() && m.second["texture"]) addFile(m.second["texture"]);
  f.add(flowYaml(referenceOverrides(s)));
  f.add(s.reference.integrator);
  f.add(flowYaml(s.reference.params));
  // Not the budget: the same chunks serve any budget, and more of them extend it.
  f.add(std::to_string(s.reference.chunkSpp) + "/" + std::to_string(s.reference.seed));
  return f.hex();
}

std::string referenceBudget(const ReferenceSpec& r) {
  std::ostringstream out;
  if (r.seconds > 0) out << r.seconds << " s";
  else if (r.noiseFloor > 0) out << "noise floor " << r.noiseFloor;
  else out << r.spp << " spp";
  return out.str();
}

namespace {

// Fewest chunks before a noise floor is trusted: the variance across chunks
// has chunks − 1 degrees of freedom per pixel, and a caustic's noise is
// heavy-tailed (a few pixels hold most of it), so a handful of chunks
// underestimates it too often.
constexpr uint64_t MinChunksForFloor = 16;

// A noise floor too low to reach (1e-30) stops at the 30 days a time budget
// may ask for (issue 34, class 5), and says so (floorNotReached).
bool budgetMet(const ReferenceSpec& r, uint64_t chunks, double seconds, double varianceOfMean) {
  if (r.spp > 0) return chunks * r.chunkSpp >= r.spp;  // 1 spp: one chunk, no variance
  if (chunks < 2) return false;
  if (r.seconds > 0) return seconds >= r.seconds;
  return (chunks >= MinChunksForFloor && std::sqrt(varianceOfMean) <= r.noiseFloor) || seconds >= kMaxBudgetSeconds;
}

bool floorNotReached(const ReferenceSpec& r, double varianceOfMean) {
  return r.noiseFloor > 0 && !(std::sqrt(varianceOfMean) <= r.noiseFloor);
}

// A variance image that overflowed a float (a reference brighter than its
// squares can hold) would empty the comparisons' columns (issue 34, class 1):
// refused where it is computed, naming the pixel.
void checkFiniteVariance(const ExperimentScene& s, const Image& variance, const std::string& what) {
  for (size_t i = 0; i < variance.pixels.size(); ++i) {
    const Color& c = variance.pixels[i];
    if (!(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)))
      throw s.referenceAt.error(what + ": its per-pixel variance is beyond a float's range at pixel (" +
                                std::to_string(i % size_t(variance.width)) + ", " +
                                std::to_string(i / size_t(variance.width)) + "); the scene's radiance is too large");
  }
}

struct CachePaths {
  std::filesystem::path mean, variance, sidecar;
};

std::string fileHash(const std::filesystem::path& a, const std::filesystem::path& b) {
  return hashStrings({readBytes(a.string()), readBytes(b.string())});
}

}  // namespace

SceneFile loadReferenceScene(const ExperimentScene& s) {
  SceneLoadOptions quiet;
  quiet.quiet = true;  // validateExperiment printed the scene's import warnings
  return loadScene(referenceScene(s), referenceOverrides(s), quiet);
}

RenderedChunk renderReferenceChunk(const ExperimentScene& s, const SceneFile& sf, uint64_t k) {
  // A new integrator per chunk: chunks are independent renders (a
  // progressive integrator's state would otherwise carry over). For a
  // consistent one (allowed with allow_biased_reference) each chunk is its
  // own chunk_spp-pass render, so its bias is that of chunk_spp passes,
  // however many chunks are averaged.
  Params params(withSharedIntegratorKeys(sf, s.reference.params, keysReadBy(s.reference.integrator)), s.path,
                "reference.params");
  auto integrator = makeIntegrator(s.reference.integrator, params);
  return renderChunk(*sf.scene, *integrator, sf.sampler, s.reference.seed, k, s.reference.chunkSpp);
}

Reference obtainReference(const ExperimentScene& s, const std::string& resultsRoot, const std::string& key,
                          const RemoteChunks* remote) {
  if (!s.reference.file.empty()) {
    std::cerr << "reference: " << s.reference.file << " (given)\n";
    Reference r;
    r.image = readExr(s.reference.file);
    r.description = "file " + s.reference.file;
    return r;
  }
  const ReferenceSpec& spec = s.reference;
  std::filesystem::path dir = std::filesystem::path(resultsRoot) / "references";
  std::filesystem::create_directories(dir);
  std::string stem = referenceName(s) + "-" + key;
  CachePaths cache{dir / (stem + ".exr"), dir / (stem + ".variance.exr"), dir / (stem + ".yaml")};

  SceneFile sf = loadReferenceScene(s);
  const int width = sf.scene->camera.width(), height = sf.scene->camera.height();
  ChunkAccumulator acc(width, height);
  double seconds = 0;
  uint64_t nonFinite = 0;
  // The cache as last saved, if its files agree with each other: the sidecar
  // names the hash of the two images (checked before they are read) and the
  // chunk count. False when absent or inconsistent.
  auto loadCache = [&]() {
    acc = ChunkAccumulator(width, height), seconds = 0, nonFinite = 0;
    if (!std::filesystem::exists(cache.sidecar) || !std::filesystem::exists(cache.mean) ||
        !std::filesystem::exists(cache.variance))
      return false;
    // The sidecar is ours, but a user may have edited or truncated it.
    Params info(loadYamlFile(cache.sidecar.string()), cache.sidecar.string(), "");
    uint64_t chunks = uint64_t(info.getInt("chunks", 0));
    double cachedSeconds = info.getFloat("seconds", 0);
    std::string hash = info.getString("files_hash", "");
    if (info.has("variance_of_mean")) info.getFloat("variance_of_mean", 0);
    if (chunks < 1 || hash != fileHash(cache.mean, cache.variance)) return false;
    Image mean = readExr(cache.mean.string()), variance = readExr(cache.variance.string());
    if (mean.width != width || mean.height != height || variance.width != width || variance.height != height)
      return false;
    // Only an older build wrote one (this one refuses before writing): not
    // removed here, outside the references folder's lock; the message says so.
    checkFiniteVariance(s, variance, "cached reference " + cache.variance.string() + " (delete it and its .exr and .yaml)");
    acc.restore(mean, variance, chunks);
    seconds = cachedSeconds;
    nonFinite = uint64_t(info.getInt("non_finite_samples", 0));
    return true;
  };
  auto result = [&](const char* how) {
    Reference r;
    r.image = acc.meanImage();
    r.varianceOfMean = acc.varianceOfMean();
    r.chunks = acc.chunks;
    r.chunkSpp = spec.chunkSpp;
    if (acc.chunks > 1) r.variance = acc.varianceOfMeanImage();
    std::ostringstream d;
    d << spec.integrator << " " << flowYaml(spec.params) << ", " << acc.chunks << " chunks of " << spec.chunkSpp
      << " spp (" << acc.chunks * spec.chunkSpp << " spp), " << std::lround(seconds) << " s, " << how;
    r.description = d.str();
    std::cerr << "reference: " << cache.mean.string() << " (" << d.str() << ", noise floor "
              << std::sqrt(r.varianceOfMean) << ")\n";
    if (floorNotReached(spec, r.varianceOfMean))
      std::cerr << "warning: reference " << referenceName(s) << " stopped at 30 days (the longest budget) above its "
                << "noise_floor " << spec.noiseFloor << "\n";
    return r;
  };
  if (loadCache() && budgetMet(spec, acc.chunks, seconds, acc.varianceOfMean())) return result("cached");

  // Rendering: one process at a time per references folder (three shipped
  // experiments share the glass sphere's), and the cache read again once
  // the lock is held, since another process may have just extended it.
  RunLock lock(dir.string(), s.path, "references folder");
  bool cached = loadCache();
  if (cached && budgetMet(spec, acc.chunks, seconds, acc.varianceOfMean())) return result("cached");
  if (!cached && std::filesystem::exists(cache.sidecar))
    std::cerr << "reference: " << cache.mean.string() << " does not match its sidecar (an interrupted write, an "
              << "edit or another size); rendering it anew\n";
  std::cerr << "reference: " << (acc.chunks ? "extending " : "rendering ") << referenceName(s) << " with '"
            << spec.integrator << "' to " << referenceBudget(spec) << " in chunks of " << spec.chunkSpp
            << " spp (cached as " << cache.mean.string() << "; an interrupted render keeps its finished chunks)\n";
  if (acc.chunks == 0) seconds = sf.scene->buildSeconds();
  // Each chunk as it comes, in chunk order; false once the budget is met.
  auto take = [&](RenderedChunk&& chunk) {
    acc.add(chunk.image);
    seconds += chunk.seconds;
    nonFinite += chunk.nonFinite;

    // Saved after every chunk: the mean and variance images first, then the
    // sidecar naming their hash (a write cut between them is detected above).
    Image varianceImage = acc.varianceOfMeanImage();
    try {
      checkFiniteVariance(s, varianceImage, "reference " + referenceName(s));
    } catch (const ConfigError&) {
      // A refused reference leaves no chunk behind to be served later.
      std::error_code ec;  // the refusal stays the error, whatever removing gives
      for (const auto& f : {cache.mean, cache.variance, cache.sidecar}) std::filesystem::remove(f, ec);
      throw;
    }
    writeExr(cache.mean.string(), acc.meanImage());
    writeExr(cache.variance.string(), varianceImage);
    double v = acc.varianceOfMean();
    YAML::Emitter info;  // an emitter: a scene path with ": " or "#" stays valid YAML
    info << YAML::BeginMap << YAML::Key << "scene" << YAML::Value << referenceScene(s) << YAML::Key << "integrator"
         << YAML::Value << spec.integrator << YAML::Key << "params" << YAML::Value << flowYaml(spec.params)
         << YAML::Key << "chunk_spp" << YAML::Value << spec.chunkSpp << YAML::Key << "chunks" << YAML::Value
         << acc.chunks << YAML::Key << "spp" << YAML::Value << acc.chunks * spec.chunkSpp << YAML::Key << "seed"
         << YAML::Value << spec.seed << YAML::Key << "seconds" << YAML::Value << seconds << YAML::Key
         << "non_finite_samples" << YAML::Value << nonFinite;
    if (std::isfinite(v))
      info << YAML::Key << "variance_of_mean" << YAML::Value << v << YAML::Key << "noise_floor" << YAML::Value
           << std::sqrt(v);
    info << YAML::Key << "files_hash" << YAML::Value << fileHash(cache.mean, cache.variance) << YAML::Key << "key"
         << YAML::Value << key << YAML::EndMap;
    writeTextFile(cache.sidecar.string(), std::string(info.c_str()) + "\n");

    std::ostringstream line;
    line << "reference " << referenceName(s) << ": chunk " << acc.chunks << " (" << acc.chunks * spec.chunkSpp
         << " spp, " << formatSeconds(seconds) << ")";
    if (acc.chunks >= 2) line << ", noise floor " << std::setprecision(3) << std::sqrt(v);
    // Its own ETA, from the time per chunk so far.
    if (spec.spp > 0) {
      double chunksLeft = std::ceil(double(spec.spp) / spec.chunkSpp) - double(acc.chunks);
      if (chunksLeft > 0) line << ", ETA " << formatSeconds(seconds / acc.chunks * chunksLeft);
    } else if (spec.seconds > 0 && seconds < spec.seconds) {
      line << ", ETA " << formatSeconds(spec.seconds - seconds);
    }
    if (spec.noiseFloor > 0 && acc.chunks >= 2 && std::sqrt(v) > spec.noiseFloor)
      // The floor falls as 1/sqrt(time): about (floor/target)² times the time so far.
      line << " → " << spec.noiseFloor << ", about " << std::setprecision(3)
           << seconds * (v / (double(spec.noiseFloor) * spec.noiseFloor) - 1) << " s more";
    std::cerr << line.str() << "\n";
    return !budgetMet(spec, acc.chunks, seconds, acc.varianceOfMean());
  };
  // A sample budget knows its last chunk; a time or noise budget is checked after each.
  uint64_t end = spec.spp > 0 ? std::max<uint64_t>(1, (spec.spp + spec.chunkSpp - 1) / spec.chunkSpp) : OpenEnded;
  if (!budgetMet(spec, acc.chunks, seconds, acc.varianceOfMean())) {
    if (remote)
      renderChunksOnFarm(remote->farm, acc.chunks, end, remote->task, take);
    else
      renderChunksHere(acc.chunks, end, [&](uint64_t k) { return renderReferenceChunk(s, sf, k); }, take);
  }
  return result("rendered");
}

}  // namespace lb
