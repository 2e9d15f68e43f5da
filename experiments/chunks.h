#pragma once
// A long render as independent seeded chunks (issues 13 and 19): chunk k is a
// render of chunkSpp passes with seed chunkSeed(seed, k), by a fresh
// integrator, and the result is the mean of the chunks, accumulated in chunk
// order. A chunk's image does not depend on the thread count (integrator.h),
// so the mean is bit-identical whether the chunks were rendered one after
// another here or by any number of MPI ranks (renderChunksOnFarm): the order
// of the sum, not the order of arrival, fixes the bits.
//
// Cached references (reference.h) and `lightbench render --distributed` are
// rendered so.
#include <functional>
#include <memory>
#include <vector>
#include "core/image.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "experiments/cluster.h"
#include "integrators/integrator.h"

namespace lb {

// Chunk k's seed: mixed (splitmix64), so no chunk shares a seed with a run
// (runs use seed + 7919·repeat) or with another chunk.
uint64_t chunkSeed(uint64_t seed, uint64_t k);

struct RenderedChunk {
  Image image;
  double seconds = 0;  // preprocess + passes
  uint64_t nonFinite = 0, rays = 0;
};

RenderedChunk renderChunk(const Scene& scene, Integrator& freshIntegrator, const SamplerSettings& sampler,
                          uint64_t seed, uint64_t chunk, uint64_t chunkSpp);

// The running mean and sum of squared deviations over chunks, per pixel and
// channel (Welford's update, in chunk order).
struct ChunkAccumulator {
  int width = 0, height = 0;
  uint64_t chunks = 0;
  std::vector<glm::dvec3> mean, m2;

  ChunkAccumulator(int w, int h) : width(w), height(h), mean(size_t(w) * h, glm::dvec3(0)), m2(mean) {}
  void add(const Image& chunk);
  Image meanImage() const;
  // The variance of the mean of the chunks: the sample variance across chunks
  // divided by their number. Needs two chunks.
  Image varianceOfMeanImage() const;
  double varianceOfMean() const;  // over pixels and channels; NaN below two chunks
  // Back from a cache: m2 = variance of the mean × n(n − 1).
  void restore(const Image& meanImage, const Image& varianceOfMean, uint64_t n);
};

// Renders chunks first, first + 1, … (below `end`) and hands each to `take`
// in chunk order until `take` returns false.
using ChunkTaker = std::function<bool(RenderedChunk&&)>;
constexpr uint64_t OpenEnded = ~uint64_t(0);
// Here, one after another, with `render(k)`.
void renderChunksHere(uint64_t first, uint64_t end, const std::function<RenderedChunk(uint64_t)>& render,
                      const ChunkTaker& take);
// By the farm's workers: `task(k)` is the task that makes a worker render
// chunk k and answer with chunkResult(k, …). Chunks that arrive early wait for
// their turn, at most two per worker ahead of the first not yet taken. With
// an open end (a time or noise budget) idle workers start later chunks before
// `take` has decided: those out or waiting when it says stop are rendered in
// vain and dropped, fewer than two per worker.
void renderChunksOnFarm(Farm& farm, uint64_t first, uint64_t end, const std::function<std::string(uint64_t)>& task,
                        const ChunkTaker& take);

// A whole render as chunks (`lightbench render --distributed`): spp passes
// in chunks of chunkSpp (a divisor), each by a fresh integrator from `fresh`;
// by the farm's workers when `farm` has any (a task is `identity` and k: the
// worker checks the identity, renders chunk k with renderChunk and answers
// with chunkResult), else here.
struct ChunkedRender {
  Image mean, varianceOfMean;
  uint64_t chunks = 0, passes = 0, nonFinite = 0, rays = 0;
  double seconds = 0;       // wall time of the whole render
  double chunkSeconds = 0;  // the chunks' own times, summed
};
ChunkedRender renderChunked(const Scene& scene, const SamplerSettings& sampler,
                            const std::function<std::unique_ptr<Integrator>()>& fresh, uint64_t seed, uint64_t spp,
                            uint64_t chunkSpp, Farm* farm, const std::string& identity, bool progress);

// A worker's answer to a chunk task.
std::string chunkResult(uint64_t k, const RenderedChunk& chunk);

}  // namespace lb
