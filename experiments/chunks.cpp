#include "experiments/chunks.h"
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include "integrators/render_loop.h"

namespace lb {

uint64_t chunkSeed(uint64_t seed, uint64_t k) {
  uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (k + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

RenderedChunk renderChunk(const Scene& scene, Integrator& integrator, const SamplerSettings& sampler, uint64_t seed,
                          uint64_t chunk, uint64_t chunkSpp) {
  Film film(scene.camera.width(), scene.camera.height());
  RenderOptions options;
  options.seed = chunkSeed(seed, chunk);
  options.budget.spp = chunkSpp;
  RenderReport rep = renderLoop(scene, integrator, film, sampler, options);
  return {film.image(), rep.seconds, rep.nonFinite, rep.rays};
}

void ChunkAccumulator::add(const Image& chunk) {
  ++chunks;
  for (size_t i = 0; i < mean.size(); ++i) {
    glm::dvec3 x(chunk.pixels[i]);
    glm::dvec3 d = x - mean[i];
    mean[i] += d / double(chunks);
    m2[i] += d * (x - mean[i]);
  }
}

Image ChunkAccumulator::meanImage() const {
  Image out(width, height);
  for (size_t i = 0; i < mean.size(); ++i) out.pixels[i] = Color(mean[i]);
  return out;
}

Image ChunkAccumulator::varianceOfMeanImage() const {
  Image out(width, height);
  double scale = chunks > 1 ? 1.0 / (double(chunks - 1) * double(chunks)) : 0.0;
  for (size_t i = 0; i < m2.size(); ++i) out.pixels[i] = Color(m2[i] * scale);
  return out;
}

double ChunkAccumulator::varianceOfMean() const {
  if (chunks < 2) return NAN;
  double sum = 0;
  for (const auto& v : m2) sum += v.x + v.y + v.z;
  return sum / (3.0 * double(m2.size()) * double(chunks - 1) * double(chunks));
}

void ChunkAccumulator::restore(const Image& meanImage, const Image& varianceOfMean, uint64_t n) {
  chunks = n;
  for (size_t i = 0; i < mean.size(); ++i) {
    mean[i] = glm::dvec3(meanImage.pixels[i]);
    m2[i] = glm::dvec3(varianceOfMean.pixels[i]) * (double(n) * double(n - 1));
  }
}

void renderChunksHere(uint64_t first, uint64_t end, const std::function<RenderedChunk(uint64_t)>& render,
                      const ChunkTaker& take) {
  for (uint64_t k = first; k < end && take(render(k)); ++k) {
  }
}

void renderChunksOnFarm(Farm& farm, uint64_t first, uint64_t end, const std::function<std::string(uint64_t)>& task,
                        const ChunkTaker& take) {
  uint64_t nextTask = first, nextTaken = first;
  bool done = false;
  std::map<uint64_t, RenderedChunk> early;  // arrived before an earlier chunk
  farm.distribute(
      [&](int) -> std::optional<std::string> {
        // Look ahead at most two chunks per worker past the first not yet
        // taken: bounded memory for early arrivals, and bounded waste once
        // `take` says stop.
        if (done || nextTask >= end || nextTask >= nextTaken + 2 * uint64_t(farm.workers())) return std::nullopt;
        return task(nextTask++);
      },
      [&](int, std::string&& bytes) {
        ByteReader r(bytes);
        uint64_t k = r.u64();
        if (done) return;
        RenderedChunk c;
        c.image = r.image();
        c.seconds = r.f64();
        c.nonFinite = r.u64();
        c.rays = r.u64();
        early.emplace(k, std::move(c));
        for (auto it = early.find(nextTaken); it != early.end() && !done; it = early.find(nextTaken)) {
          done = !take(std::move(it->second));
          early.erase(it);
          ++nextTaken;
        }
      });
}

ChunkedRender renderChunked(const Scene& scene, const SamplerSettings& sampler,
                            const std::function<std::unique_ptr<Integrator>()>& fresh, uint64_t seed, uint64_t spp,
                            uint64_t chunkSpp, Farm* farm, const std::string& identity, bool progress) {
  auto start = std::chrono::steady_clock::now();
  ChunkAccumulator acc(scene.camera.width(), scene.camera.height());
  ChunkedRender out;
  const uint64_t chunks = spp / chunkSpp;
  auto take = [&](RenderedChunk&& c) {
    acc.add(c.image);
    out.chunkSeconds += c.seconds;
    out.nonFinite += c.nonFinite;
    out.rays += c.rays;
    if (progress) std::fprintf(stderr, "\rchunk %llu/%llu", (unsigned long long)acc.chunks, (unsigned long long)chunks);
    return true;
  };
  if (farm && farm->workers() > 0)
    renderChunksOnFarm(
        *farm, 0, chunks, [&](uint64_t k) { return ByteWriter().str(identity).u64(k).take(); }, take);
  else
    renderChunksHere(
        0, chunks,
        [&](uint64_t k) {
          auto integrator = fresh();
          return renderChunk(scene, *integrator, sampler, seed, k, chunkSpp);
        },
        take);
  if (progress) std::fprintf(stderr, "\n");
  out.mean = acc.meanImage();
  out.varianceOfMean = acc.varianceOfMeanImage();
  out.chunks = acc.chunks;
  out.passes = acc.chunks * chunkSpp;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::string chunkResult(uint64_t k, const RenderedChunk& c) {
  return ByteWriter().u64(k).image(c.image).f64(c.seconds).u64(c.nonFinite).u64(c.rays).take();
}

}  // namespace lb
