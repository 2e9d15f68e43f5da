// The bidirectional MIS weights (BDPT's, and VCM's below) against an independent computation (issue: "Every
// integrator estimates the same integral"). For random paths sampled by the
// integrator's own subpath and connection code, every strategy's density is
// recomputed from its definition (tests/support/path_pdfs.h: O(n²), no ratio
// recursion, double precision) and the integrator's weight must equal the
// heuristic applied to those densities. Σw = 1 alone would not catch wrong
// densities: pbrt-v3's treatment of specular chains sums to 1 and still gave
// the camera strategy ~96 % of a glass caustic that light tracing samples
// ~100× better.
#include <gtest/gtest.h>
#include <functional>
#include <algorithm>
#include "core/sampler.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/bidirectional/subpaths.h"
#include "integrators/bidirectional/verification.h"
#include "tests/support/path_pdfs.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

using bidir::MisWeighting;

using bidir::Vertex;

// Floor, smooth glass, rough glass, a glossy and a mirror sphere: diffuse,
// glossy and specular vertices, and glass chains; the light is appended.
const std::string kMaterialsScene =
    "camera: {position: [0, 2.2, 5], look_at: [0, 0.5, 0], fov: 40}\n"
    "film: {width: 32, height: 24}\n"
    "materials: {floor: {type: diffuse, albedo: 0.7}, glass: {type: dielectric, ior: 1.5},\n"
    "            frosted: {type: dielectric, ior: 1.3, roughness: 0.3},\n"
    "            metal: {type: conductor, roughness: 0.2}, mirror: {type: conductor}}\n"
    "shapes:\n"
    "  - {type: rectangle, material: floor, transform: {scale: 5, rotate_x: -90}}\n"
    "  - {type: rectangle, material: floor, transform: {scale: 5, translate: [0, 0, -2]}}\n"
    "  - {type: sphere, material: glass, center: [-0.9, 0.5, 0], radius: 0.5}\n"
    "  - {type: sphere, material: frosted, center: [0.2, 0.4, 0.6], radius: 0.4}\n"
    "  - {type: sphere, material: metal, center: [1.1, 0.5, -0.2], radius: 0.5}\n"
    "  - {type: sphere, material: mirror, center: [0, 1.4, -1], radius: 0.4}\n";

const std::string kFlatWaterScene =
    "camera: {position: [0, 2.2, 3], look_at: [0, 0, 0], fov: 45}\n"
    "film: {width: 32, height: 24}\n"
    "materials: {floor: {type: diffuse, albedo: 0.7}, water: {type: dielectric, ior: 1.33},\n"
    "            metal: {type: conductor, roughness: 0.2}}\n"
    "shapes:\n"
    "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90}}\n"
    "  - {type: rectangle, material: floor, transform: {scale: 3, translate: [0, 0, -1.5]}}\n"
    "  - {type: rectangle, material: water, transform: {scale: 3, rotate_x: -90, translate: [0, 0.5, 0]}}\n"
    "  - {type: sphere, material: metal, center: [0.5, 0.9, -0.4], radius: 0.3}\n"
    "  - {type: sphere, material: none, center: [-0.6, 2.2, 0.5], radius: 0.15, emission: 40}\n"
    "  - {type: sphere, material: none, center: [0.4, 0.2, 0.3], radius: 0.08, emission: 40}\n";
const std::string kLightInGlassScene =
    "camera: {position: [0, 1.6, 3.2], look_at: [0, 0.3, 0], fov: 45}\n"
    "film: {width: 32, height: 24}\n"
    "materials: {floor: {type: diffuse, albedo: 0.7}, glass: {type: dielectric, ior: 1.5}}\n"
    "shapes:\n"
    "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90}}\n"
    "  - {type: rectangle, material: floor, transform: {scale: 3, translate: [0, 0, -1.5]}}\n"
    "  - {type: box, material: glass, transform: {scale: [0.6, 0.25, 0.4], translate: [0, 0.6, 0]}}\n"
    "  - {type: sphere, material: none, center: [0.1, 0.6, 0], radius: 0.1, emission: 60}\n";

struct Case {
  std::string name;
  SceneFile scene;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"cornell-box-spheres", loadShippedScene("cornell-box-spheres", 32, 32)});
  c.push_back({"veach-mis", loadShippedScene("veach-mis", 40, 25)});
  const std::pair<const char*, const char*> lights[] = {
      {"sphere light", "  - {type: sphere, material: none, center: [0.3, 2.5, 0.8], radius: 0.15, emission: 60}\n"},
      {"area light", "  - {type: rectangle, material: none, emission: 30,\n"
                     "     transform: {scale: 0.3, rotate_x: 90, translate: [-0.4, 2.6, 0.3]}}\n"},
      {"point light", "lights: [{type: point, position: [0.4, 2.5, 1], intensity: 10}]\n"},
      {"spot light", "lights: [{type: spot, position: [-0.5, 2.5, 1.5], look_at: [0, 0, 0], intensity: 20, cone_angle: 40}]\n"},
      {"directional light", "lights: [{type: directional, direction: [-0.4, -1, -0.6], irradiance: 2}]\n"},
      {"environment", "lights: [{type: environment, radiance: 1}]\n"},
  };
  for (auto [name, yaml] : lights) c.push_back({name, loadSceneFromString(kMaterialsScene + yaml, "mis.yaml")});
  // One flat interface, where the refraction Jacobian does not cancel
  // between the two crossings of a chord (vertex.h): a water surface with
  // lights above and below it (the camera above), and a light inside a glass
  // slab, every path leaving it through one face.
  c.push_back({"flat water", loadSceneFromString(kFlatWaterScene, "water.yaml")});
  c.push_back({"light in glass", loadSceneFromString(kLightInGlassScene, "slab.yaml")});
  return c;
}

// Float rounding allowance for one weight. The integrator's densities are
// float products of ~4 factors per vertex, and the cached ones were taken
// along the sampled ray, whose origin is offset from the stored vertex by at
// most the error bound the offset uses, γ(7)(|a| + |b|)/d in angle; a density
// with a slope k in the angle (cosines: k = tan θ; glossy lobes up to ~2/α²·θ)
// turns that into a relative error k·ε. With every ratio's relative error at
// most δ, a weight w = 1 / (1 + Σ r^β) moves by at most β·δ·w(1 − w) ≤ β·δ/4.
// Returns a negative allowance for a path with a segment so close to grazing
// that the side of a surface it leaves or meets is not determined by the
// float positions (|cos θ| within the angle error ε): there a BSDF's
// same-side test may differ between the sampled ray and the stored vertices.
double allowance(const std::vector<Vertex>& path, MisWeighting h) {
  double delta = 0;
  for (size_t i = 1; i < path.size(); ++i) {
    const Vertex &a = path[i - 1], &b = path[i];
    if (b.isInfiniteLight() || a.isInfiniteLight()) continue;
    float d = glm::length(b.p - a.p);
    if (!(d > 0)) return -1;  // coincident vertices: no direction at all
    float eps = gamma(7) * (maxComponent(glm::abs(a.p)) + maxComponent(glm::abs(b.p))) / std::max(d, 1e-30f);
    float slope = 2 / sqr(0.2f);  // the roughest lobe slope the scenes' glossy materials reach near their peak
    // Every vertex on a surface, an area light's point too: its cosine is in
    // the emission density (a ray leaving a ceiling light at cos 0.0015
    // towards a wall point just below the ceiling: slope ~700).
    for (const Vertex* v : {&a, &b})
      if (v->onSurface()) {
        float cos = absDot(v->ng, (b.p - a.p) / d);
        if (!(cos > 4 * eps)) return -1;
        slope += std::sqrt(std::max(0.f, 1 - cos * cos)) / std::max(cos, 1e-6f);
      }
    delta += 2 * (16 * std::numeric_limits<float>::epsilon() + double(slope) * eps);  // both directions' densities
  }
  return (h == MisWeighting::Power ? 2.0 : 1.0) * delta / 4;
}

struct Stats {
  int compared = 0, grazing = 0, withSpecular = 0, longest = 0;
  int merges = 0, causticMerges = 0;  // VCM: merge weights checked (expected > 0), behind a specular light vertex
  double worst = 0;  // largest |error| / allowance
};

// `connectionCount`: the light-vertex-cache BDPT's expected draws per
// connection with s, t >= 2 (mis.h, Techniques::connectionCount); the
// definition multiplies those strategies' densities by it.
// `factor`: variance-aware MIS's per-strategy factors (strategy_factors.h):
// the definition multiplies strategy (s', t')'s density by factor(s', t'),
// and only the walk, which takes them, is compared.
void compareOnScene(const Case& c, MisWeighting h, uint64_t samples, Stats& st, double connectionCount = 1,
                    const std::function<double(int, int)>* factor = nullptr) {
  const Scene& scene = *c.scene.scene;
  BdptSettings settings;
  settings.length.maxDepth = 8;
  settings.length.russianRoulette = false;
  settings.mis = h;
  std::vector<Vertex> camera(10), light(10);
  IndependentSampler sampler(17);
  uint64_t rays = 0;
  int W = scene.camera.width(), H = scene.camera.height();
  for (uint64_t i = 0; i < samples; ++i) {
    sampler.start(i, 0);
    int nc = bidir::generateCameraSubpath(scene, sampler, settings.length, Vec2(sampler.get1D() * W, sampler.get1D() * H), camera, rays);
    int nl = bidir::generateLightSubpath(scene, sampler, settings.length, light, rays);
    bidir::Techniques techniques;
    techniques.connectionCount = connectionCount;
    bidir::computePartialSums(scene, h, techniques, camera, nc, bidir::SubpathSide::Camera);
    bidir::computePartialSums(scene, h, techniques, light, nl, bidir::SubpathSide::Light);
    for (int t = 1; t <= nc; ++t)
      for (int s = 0; s <= std::max(nl, 1); ++s) {
        if ((s == 1 && t == 1) || s + t < 3 || s + t - 1 > 8) continue;
        bidir::Connection con = bidir::connect(scene, sampler, settings.mis, techniques, light, camera, s, t, rays);
        if (isBlack(con.L)) continue;
        std::vector<Vertex> path;
        if (t == 1) path.push_back(con.sampled);
        else path.insert(path.end(), camera.begin(), camera.begin() + t);
        if (s == 1) path.push_back(con.sampled);
        else for (int k = s - 1; k >= 0; --k) path.push_back(light[size_t(k)]);
        std::vector<double> pdfs = strategyPdfsFromDefinition(scene, path);
        for (size_t sOther = 2; sOther + 2 <= path.size(); ++sOther) pdfs[sOther] *= connectionCount;  // t' >= 2
        if (factor)
          for (size_t sOther = 0; sOther < pdfs.size(); ++sOther)
            pdfs[sOther] *= (*factor)(int(sOther), int(path.size() - sOther));
        std::vector<double> w = weightsFromPdfs(pdfs, h);
        double weight = factor ? bidir::techniqueWeightsByWalk(scene, h, techniques, light, camera, con.sampled, s, t,
                                                               nullptr, factor)
                                     .connection
                               : con.weight;
        double err = std::abs(double(weight) - w[size_t(s)]), allowed = allowance(path, h);
        if (allowed < 0) {
          ++st.grazing;
          continue;
        }
        st.worst = std::max(st.worst, err / allowed);
        ++st.compared;
        st.longest = std::max(st.longest, s + t - 1);
        for (const Vertex& v : path) st.withSpecular += v.delta ? 1 : 0;
        ASSERT_LE(err, allowed) << c.name << ": strategy (" << s << ", " << t << ") of a path of " << s + t - 1
                                << " segments, weight " << weight << ", from the definition " << w[size_t(s)];
        if (factor) continue;
        // The O(s + t) walk the partial sums replaced (verification.h), kept as a debugging aid.
        float walk = bidir::techniqueWeightsByWalk(scene, h, techniques, light, camera, con.sampled, s, t).connection;
        ASSERT_LE(std::abs(double(walk) - w[size_t(s)]), allowed)
            << c.name << ": the walk's weight of (" << s << ", " << t << "): " << walk << ", from the definition "
            << w[size_t(s)];
      }
  }
}

TEST(BdptMis, WeightsEqualTheHeuristicOfIndependentlyComputedDensities) {
  int longest = 0;
  for (const Case& c : cases())
    for (MisWeighting h : {MisWeighting::Power, MisWeighting::Balance, MisWeighting::Uniform}) {
      Stats st;
      compareOnScene(c, h, 1500, st);
      if (HasFatalFailure()) return;
      std::printf("%-20s heuristic %d: %d weights (%d grazing, skipped), %d specular vertices, up to %d segments, "
                  "worst error %.3g of its allowance\n",
                  c.name.c_str(), int(h), st.compared, st.grazing, st.withSpecular, st.longest, st.worst);
      EXPECT_GT(st.compared, 1000) << c.name;
      // Coverage, not a tolerance: a test that skipped more than 1 in 20 of
      // its paths would not test what it claims. (Measured: at most 32 of
      // 2330, the environment lighting the floor's underside, joined to its
      // top within the floor's plane.)
      EXPECT_LT(st.grazing, st.compared / 20) << c.name;
      EXPECT_GE(st.longest, 6) << c.name;
      if (c.name != "veach-mis") {
        EXPECT_GT(st.withSpecular, 100) << c.name;
      }
      longest = std::max(longest, st.longest);
    }
  EXPECT_EQ(longest, 8);  // paths of 2…8 segments
}

// The light-vertex-cache BDPT (vcm mode lvc) counts each connection with
// s, t >= 2 k·N/M times per sample: its weights against the same definition
// with those strategies' densities scaled, from far below 1 to far above
// (at 1 a misplaced factor would be invisible), on every case above: the
// scenes where next-event estimation (s = 1) and light tracing (t = 1), which
// keep count 1, are each another strategy's neighbour.
TEST(LvcMis, WeightsEqualTheHeuristicOfIndependentlyComputedDensities) {
  for (const Case& c : cases())
    for (MisWeighting h : {MisWeighting::Power, MisWeighting::Balance})
      for (double count : {1e-3, 0.3, 40.0}) {
        Stats st;
        compareOnScene(c, h, 300, st, count);
        if (HasFatalFailure()) return;
        EXPECT_GT(st.compared, 150) << c.name;
        EXPECT_LT(st.grazing, st.compared / 20 + 1) << c.name;
      }
}

// Variance-aware MIS for BDPT (bdpt mis: variance_aware) weighs by the walk
// with a factor per strategy (s', t'): against the definition with each
// strategy's density scaled by its factor, factors from 0.01 to 100 that
// differ between every two strategies of a path (equal ones would cancel).
TEST(BdptVarianceAwareMis, WalkWithFactorsEqualsTheBalanceHeuristicOfScaledDensities) {
  std::function<double(int, int)> factor = [](int s, int t) { return std::exp(4.6 * std::sin(7.1 * s + 3.3 * t)); };
  for (const Case& c : cases()) {
    Stats st;
    compareOnScene(c, MisWeighting::Balance, 300, st, 1, &factor);
    if (HasFatalFailure()) return;
    EXPECT_GT(st.compared, 150) << c.name;
    EXPECT_LT(st.grazing, st.compared / 20 + 1) << c.name;
  }
}

// The same check for vertex connection and merging's weights (issue 13):
// connections and merges at every interior non-specular vertex compete, each
// merge with density m_k = (its connection's) · p_light(x_k) · η. For every
// connection (s, t) of a sampled pair of subpaths, and every merge of
// light[0..s-1] extended to camera[t-1] at camera[t-1], the weight from
// techniqueWeights must equal the heuristic over all techniques' densities
// computed from the definition. η = N π r² takes a value that makes merges
// negligible, comparable and dominant; connections on (vcm) and off (bpm).
void compareVcmOnScene(const Case& c, MisWeighting h, bidir::Techniques techniques, uint64_t samples, Stats& st) {
  const Scene& scene = *c.scene.scene;
  PathLength length;
  length.maxDepth = 8;
  length.russianRoulette = false;
  std::vector<Vertex> camera(10), light(10);
  IndependentSampler sampler(23);
  uint64_t rays = 0;
  int W = scene.camera.width(), H = scene.camera.height();
  auto definition = [&](const std::vector<Vertex>& path) {
    std::vector<double> pdfs = strategyPdfsFromDefinition(scene, path);
    if (!techniques.connections)
      for (size_t s = 1; s < pdfs.size(); ++s) pdfs[s] = 0;
    std::vector<double> merges = mergePdfsFromDefinition(scene, path, techniques.mergeEta);
    pdfs.insert(pdfs.end(), merges.begin(), merges.end());
    return weightsFromPdfs(pdfs, h);  // connections s = 0…n-1, then merges k = 0…n-1
  };
  auto check = [&](double weight, double expected, const std::vector<Vertex>& path, const std::string& what) {
    double err = std::abs(weight - expected), allowed = allowance(path, h);
    if (allowed < 0) return ++st.grazing, void();
    st.worst = std::max(st.worst, err / allowed);
    ++st.compared;
    st.longest = std::max(st.longest, int(path.size()) - 1);
    for (const Vertex& v : path) st.withSpecular += v.delta ? 1 : 0;
    ASSERT_LE(err, allowed) << c.name << ": " << what << " of a path of " << path.size() - 1 << " segments, weight "
                            << weight << ", from the definition " << expected;
  };
  for (uint64_t i = 0; i < samples; ++i) {
    sampler.start(i, 0);
    int nc = bidir::generateCameraSubpath(scene, sampler, length, Vec2(sampler.get1D() * W, sampler.get1D() * H), camera, rays);
    int nl = bidir::generateLightSubpath(scene, sampler, length, light, rays);
    bidir::computePartialSums(scene, h, techniques, camera, nc, bidir::SubpathSide::Camera);
    bidir::computePartialSums(scene, h, techniques, light, nl, bidir::SubpathSide::Light);
    for (int t = 1; t <= nc; ++t)
      for (int s = 0; s <= std::max(nl, 1); ++s) {
        if ((s == 1 && t == 1) || s + t < 3 || s + t - 1 > 8) continue;
        // The connection (s, t), where the connections compete.
        bidir::Connection con = bidir::connect(scene, sampler, h, light, camera, s, t, rays);
        if (!isBlack(con.L) && (techniques.connections || s == 0)) {
          std::vector<Vertex> path;
          if (t == 1) path.push_back(con.sampled);
          else path.insert(path.end(), camera.begin(), camera.begin() + t);
          if (s == 1) path.push_back(con.sampled);
          else for (int k = s - 1; k >= 0; --k) path.push_back(light[size_t(k)]);
          float w = bidir::techniqueWeights(scene, h, techniques, light, camera, con.sampled, s, t).connection;
          check(w, definition(path)[size_t(s)], path, "connection (" + std::to_string(s) + ", " + std::to_string(t) + ")");
          if (::testing::Test::HasFatalFailure()) return;
        }
      }
    // Merging: light vertex light[j] found by the camera subpath ending at
    // it. The camera subpath camera[0..t-2] is joined to a copy of light[j]
    // seen from camera[t-2], as if the camera subpath had sampled it (its
    // densities recomputed: camera[t-2] must not be specular, whose delta
    // could not point there). light[j-1] may be specular: the caustic case.
    for (int j = 1; j < nl; ++j) {
      const Vertex& q = light[size_t(j)];
      if (q.type != bidir::VertexType::Surface || !q.connectible()) continue;
      for (int t = 2; t <= nc && j + t - 1 <= 8; ++t) {
        if (camera[size_t(t - 2)].delta) continue;
        // Only joins the integrator could make: camera[t-2] sees light[j]
        // (a camera subpath reaches its merge points by tracing rays).
        const Vertex& from = camera[size_t(t - 2)];
        Ray ray = from.type == bidir::VertexType::Camera ? Ray{from.p, q.p - from.p, 1 - ShadowEpsilon}
                                                          : from.si.spawnRayTo(q.p, q.pError, q.ng);
        if (scene.occluded(ray)) continue;
        // Nor a join within a surface's plane (two floor points "see" each
        // other along it): no ray the integrator traces does that.
        if (allowance({from, q}, h) < 0) continue;
        std::vector<Vertex> cam(camera.begin(), camera.begin() + t - 1);
        const Vertex* before = t >= 3 ? &cam[size_t(t - 3)] : nullptr;
        Vertex x = q;
        x.si.wo = glm::normalize(cam.back().p - x.p);
        x.delta = false, x.pdfRev = 0;
        x.pdfFwd = bidir::vertexPdf(scene, cam.back(), before, x);
        if (t >= 4) cam[size_t(t - 3)].pdfRev = bidir::vertexPdf(scene, cam[size_t(t - 2)], &x, cam[size_t(t - 3)]);
        cam.push_back(x);
        bidir::computePartialSums(scene, h, techniques, cam, t, bidir::SubpathSide::Camera);  // densities edited above
        cam.resize(camera.size());
        std::vector<Vertex> path(cam.begin(), cam.begin() + t);
        for (int k = j - 1; k >= 0; --k) path.push_back(light[size_t(k)]);
        float w = bidir::techniqueWeights(scene, h, techniques, light, cam, Vertex{}, j, t, &q).mergeAtCamera;
        double expected = definition(path)[path.size() + size_t(t - 1)];
        check(w, expected, path, "merge at camera[" + std::to_string(t - 1) + "] with light vertex " + std::to_string(j));
        if (::testing::Test::HasFatalFailure()) return;
        if (expected > 0) ++st.merges, st.causticMerges += light[size_t(j - 1)].delta ? 1 : 0;
      }
    }
  }
}

TEST(VcmMis, WeightsEqualTheHeuristicOfIndependentlyComputedDensities) {
  std::vector<Case> all = cases();
  for (const Case* c : {&all[0], &all[2], &all[3], &all[4], &all[5], &all[6], &all[7], &all[8], &all[9]})  // all but Veach's
    for (MisWeighting h : {MisWeighting::Power, MisWeighting::Balance})
      for (float eta : {1e-3f, 1.f, 1e3f})
        for (bool connections : {true, false}) {
          Stats st;
          compareVcmOnScene(*c, h, bidir::Techniques{connections, eta}, 2000, st);
          if (::testing::Test::HasFatalFailure()) return;
          std::printf("%-20s heuristic %d, eta %g, %s: %d weights (%d merges, %d behind a specular light vertex; "
                      "%d grazing), worst error %.3g of its allowance\n",
                      c->name.c_str(), int(h), eta, connections ? "vcm" : "bpm", st.compared, st.merges,
                      st.causticMerges, st.grazing, st.worst);
          // Coverage (as above): enough weights and merges, few skipped, and
          // merges behind the glass and mirror spheres (the caustic case).
          EXPECT_GT(st.compared, 500) << c->name;
          EXPECT_GT(st.merges, 100) << c->name;
          EXPECT_LT(st.grazing, st.compared / 20) << c->name;
          if (c->name != "cornell-box-spheres") {
            EXPECT_GT(st.causticMerges, 5) << c->name;  // measured at 2000 samples: 7 (environment) to 145
          }
        }
}

}  // namespace
}  // namespace lb::test
