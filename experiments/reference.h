#pragma once
// References: an EXR given by the experiment, or one computed and cached under
// <results>/references/, keyed by a hash of everything that determines it —
// the rendering code, the scene file's bytes, the bytes of every mesh it
// names, the resolution override, the integrator, its parameters, the chunk
// size and the seed — so an edited scene or mesh never reuses a stale
// reference. The budget is not in the key: a reference is rendered as
// independent seeded chunks (issue 13), <key>.exr holds their mean and
// <key>.variance.exr its per-pixel variance (across chunks, divided by their
// number), and a larger budget later adds chunks to the cached ones.
#include <functional>
#include <string>
#include "core/scene_loader.h"
#include "core/image.h"
#include "experiments/chunks.h"
#include "experiments/experiment.h"

namespace lb {

// FNV-1a over the inputs above, as 16 hex digits.
std::string referenceKey(const ExperimentScene& scene);
// "2048 spp", "600 s" or "noise floor 0.002".
std::string referenceBudget(const ReferenceSpec& reference);
// The hash of the rendering code (core/, integrators/) this build was made
// from: part of what MPI ranks check they share and of a run's identity.
std::string renderSourceHash();
// The hash of the code integrator `name` compiles from (core/, the top of
// integrators/, its folder and the shared modules it includes; cmake/
// render_source_hash.cmake): part of every reference key, so a reference is
// rendered again when its integrator's code changes, and only then (issue
// 39). renderSourceHash() for a name with no folder.
std::string integratorSourceHash(const std::string& name);
// A file's bytes ("" if it cannot be read).
std::string fileBytes(const std::string& path);
// FNV-1a of several strings (each delimited), as 16 hex digits.
std::string hashStrings(const std::vector<std::string>& parts);

struct Reference {
  Image image;
  // The reference's own noise: mean per-pixel variance of its pixel means
  // (NaN for a given EXR). Every measured MSE includes it, so sqrt of it is
  // the RMSE floor below which no configuration can be seen to improve.
  double varianceOfMean = NAN;
  // Per pixel and channel (empty for a given EXR, or a single chunk).
  Image variance;
  uint64_t chunks = 0;  // it was estimated from (0 for a given EXR)
  uint64_t chunkSpp = 0;
  // What was used: integrator, chunks, samples, seconds (for meta.json).
  std::string description;
};
// The missing chunks rendered by a farm's workers (issue 19): task(k) makes a
// worker call renderReferenceChunk(scene, …, k) and answer with chunkResult.
// The cache then holds the same bits as a single process would write.
struct RemoteChunks {
  Farm& farm;
  std::function<std::string(uint64_t)> task;
};

// Loads or renders (and caches under `key`, the scene's referenceKey) the
// reference; reports what it did on stderr. Only this process writes the
// cache, whoever renders the chunks.
Reference obtainReference(const ExperimentScene& scene, const std::string& resultsRoot, const std::string& key,
                          const RemoteChunks* remote = nullptr);

// A worker's side: the scene a reference is rendered from (with its
// overrides), and chunk k of it.
SceneFile loadReferenceScene(const ExperimentScene& scene);
RenderedChunk renderReferenceChunk(const ExperimentScene& scene, const SceneFile& sceneFile, uint64_t k);

}  // namespace lb
