#include "tests/support/consistent_cases.h"
#include <gtest/gtest.h>
#include <cstdio>

namespace lb::test {

const ConsistentScene GlassSphere{"caustic-glass-sphere", 128, 96, 48, 64, 24, {0.05, 1e6}};
const ConsistentScene MetalRing{"metal-ring", 64, 48, 256, 64, 8, {0.2, 1e5}};
const ConsistentScene EnclosedLight{"enclosed-light", 64, 48, 64, 64, 8, {0.2, 1e5}};
const ConsistentMethod SppmMethod{"sppm",
                                  [](double p, const Scale& s) {
                                    return "{photons_per_pass: 20000, alpha: 0.99, initial_radius: " +
                                           std::to_string(s.radius * p) + "}";
                                  },
                                  24};

namespace {

struct Setup {
  const ConsistentScene* scene;
  SceneFile sf;
  std::vector<bool> mask;
  SeedMeans bdpt;
  std::map<std::string, std::unique_ptr<SceneFile>> variants;  // the scene with a method's sceneYaml
  const SceneFile& variant(const std::string& yaml) {
    if (yaml.empty()) return sf;
    std::unique_ptr<SceneFile>& v = variants[yaml];
    if (!v) v.reset(new SceneFile(loadShippedScene(scene->name, scene->width, scene->height, scene->yaml + "\n" + yaml)));
    return *v;
  }
};

std::vector<bool> pixelsCompared(const ConsistentScene& s, const SceneFile& sf) {
  if (s.regions > 1) return noEmitterSeen(*sf.scene);
  std::vector<bool> caustic = causticPixels(sf, {"light", "{}", s.ltSpp, 700}, diffusePrimaryHits(*sf.scene));
  std::printf("%s: %zu caustic pixels\n", s.name.c_str(), countTrue(caustic));
  EXPECT_GE(countTrue(caustic), 4u) << s.name << ": the caustic covers too few pixels to test";
  return caustic;
}

// One set-up per scene (its pixels and its BDPT reference), shared by its tests.
Setup& setUp(const ConsistentScene& s) {
  static std::map<std::string, std::unique_ptr<Setup>> cache;
  std::unique_ptr<Setup>& out = cache[s.name + "\n" + s.yaml];
  if (!out) {
    out.reset(new Setup{&s, loadShippedScene(s.name, s.width, s.height, s.yaml), {}, {}, {}});
    out->mask = pixelsCompared(s, out->sf);
    out->bdpt = maskedSeedMeans(out->sf, {"bdpt", "{}", s.bdptSpp, 710}, s.seeds, s.regions, out->mask);
  }
  return *out;
}

std::vector<BiasLevel> levels(Setup& s, const ConsistentMethod& m, const std::vector<double>& ps, int seeds) {
  std::vector<BiasLevel> out;
  uint64_t seed = 800;
  const SceneFile& sf = s.variant(m.sceneYaml);
  for (double p : ps) {
    out.push_back({p, maskedSeedMeans(sf, {m.integrator, m.params(p, s.scene->scale), m.spp, seed}, seeds,
                                      s.scene->regions, s.mask)});
    seed += 1000;
  }
  return out;
}

std::string label(const ConsistentCase& c) {
  return c.method.integrator + ", " + c.scene.name + (c.scene.regions > 1 ? " regions" : " caustic");
}

}  // namespace

void expectConsistentScaled(const ConsistentCase& c, const std::vector<double>& ps, double coefficient, double alpha,
                            double factor) {
  Setup& s = setUp(c.scene);
  std::vector<BiasLevel> l = levels(s, c.method, ps, c.seeds);
  if (factor != 1)
    for (BiasLevel& level : l) level.means = scaled(level.means, factor);
  int regions = c.scene.regions * c.scene.regions;
  expectBiasWithinAndShrinking(label(c), l, s.bdpt, coefficient, alpha, 3 * regions * int(l.size()));
}

void expectConsistent(const ConsistentCase& c, const std::vector<double>& ps, double coefficient, double alpha) {
  expectConsistentScaled(c, ps, coefficient, alpha, 1);
}

void printSweep(const ConsistentCase& c, const std::vector<double>& ps) {
  Setup& s = setUp(c.scene);
  printBiasSweep(label(c), levels(s, c.method, ps, c.seeds), s.bdpt);
}

}  // namespace lb::test
