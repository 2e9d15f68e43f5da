#pragma once
// The consistent integrators (photon mapping, SPPM, the irradiance cache)
// held to a bias allowance c × p against a BDPT reference on one scene
// (consistent_helpers.h): which scene and which pixels, which method and how
// its parameter p enters its settings, and the set-up shared by the tests
// of a scene. Used by consistent_caustic_test.cpp and
// consistent_scenes_test.cpp, which state the measured c's.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include "tests/support/consistent_helpers.h"

namespace lb::test {

// A method's bias parameters at p = 1 on a scene: a gather radius R0 (world
// units), a caustic photon count N0 and a global one G0.
struct Scale {
  double radius, photons, globalPhotons = 5e4;
};

struct ConsistentMethod {
  std::string integrator;
  std::function<std::string(double p, const Scale&)> params;  // YAML mapping at p
  uint64_t spp;
  std::string sceneYaml = "";  // merged into the scene (e.g. a stratified camera sampler)
};

struct ConsistentScene {
  std::string name;  // a shipped scene
  int width, height;
  uint64_t bdptSpp, ltSpp;
  int seeds;  // of the BDPT reference
  Scale scale;
  // 1: the caustic's own pixels (diffuse primary hits at least 3× the median,
  // chosen on an independent light-tracing image of ltSpp samples, as in
  // caustic_agreement_test.cpp); n > 1: an n × n grid over the pixels that
  // see no emitter.
  int regions = 1;
  std::string yaml = "";  // merged into the shipped scene for every render of it (a variant)
};

// A method on a scene, with the number of seeds its means are averaged over.
struct ConsistentCase {
  const ConsistentScene& scene;
  const ConsistentMethod& method;
  int seeds;
};

// Shared by both consistent test files (their tests set up each scene once,
// keyed by name and variant):
// the three caustic scenes, with R0 and N0 at p = 1 …
extern const ConsistentScene GlassSphere, MetalRing, EnclosedLight;
// … SPPM with its initial radius R0 p (alpha 0.99: the radius stays almost
// fixed, 24 passes × 20000 photons) …
extern const ConsistentMethod SppmMethod;
// … and stratified 8 × 8 camera samples, for caustics finer than a pixel:
// with few independent camera samples a pixel's value there is heavy-tailed
// over seeds (most samples miss the core, a few hit it). A constant, not a
// std::string: methods in other files copy it while they are initialised,
// and the order of dynamic initialisation across files is unspecified (an
// extern std::string was read empty, unstratified, in one build).
constexpr const char* Stratified = "sampler: {type: stratified, strata: 8}";
// The scenes and SppmMethod above are only referred to by other files'
// globals (ConsistentCase holds references), never copied at start-up.

// The method at p = ps[0] > ps[1] > … within c × p of BDPT and shrinking
// (expectBiasWithinAndShrinking at level alpha, Šidák over regions,
// channels and levels).
void expectConsistent(const ConsistentCase& c, const std::vector<double>& ps, double coefficient, double alpha);
// Prints the method's deviation from BDPT at each p (the sweeps the
// coefficients come from; DISABLED_ tests).
void printSweep(const ConsistentCase& c, const std::vector<double>& ps = {2, 1, 0.5, 0.25});
// The same, with every mean scaled by `factor` (the deliberate break).
void expectConsistentScaled(const ConsistentCase& c, const std::vector<double>& ps, double coefficient, double alpha,
                            double factor);

}  // namespace lb::test
