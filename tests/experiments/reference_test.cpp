// References rendered as independent seeded chunks (issue 13): their mean is
// the image, the spread across chunks its variance image, a larger budget
// extends the cache instead of starting over, and each budget (spp, seconds,
// noise floor) stops where it says.
#include <gtest/gtest.h>
#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include "experiments/reference.h"
#include "experiments/run_lock.h"

namespace fs = std::filesystem;

namespace lb {
namespace {

class ChunkedReference : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lightbench-reference-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/cornell-box.yaml", dir_ / "scene.yaml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  ExperimentScene scene(const std::string& reference, int size = 16) {
    std::ofstream(dir_ / "exp.yaml") << "scenes:\n  - scene: scene.yaml\n    resolution: [" << size << ", " << size
                                     << "]\n    reference: " << reference
                                     << "\nconfigurations:\n  - {label: pt, integrator: path}\nbudget: {spp: 1}\n";
    return loadExperiment((dir_ / "exp.yaml").string(), {}).scenes[0];
  }
  Reference obtain(const ExperimentScene& s, const std::string& results) {
    return obtainReference(s, (dir_ / results).string(), referenceKey(s));
  }
  YAML::Node sidecar(const ExperimentScene& s, const std::string& results) {
    return YAML::LoadFile((dir_ / results / "references" / ("scene-" + referenceKey(s) + ".yaml")).string());
  }
  fs::path dir_;
};

// Four chunks extended to eight equal eight rendered at once, up to the
// float32 rounding of the cached mean and variance (each stored value is
// rounded once, relative 2^-24, and rescaled by the chunk count: a few ulps).
TEST_F(ChunkedReference, ExtendingTheCacheEqualsRenderingItAtOnce) {
  ExperimentScene four = scene("{integrator: path, spp: 4, chunk_spp: 1}");
  Reference a = obtain(four, "extended");
  EXPECT_EQ(sidecar(four, "extended")["chunks"].as<int>(), 4);
  EXPECT_TRUE(std::isfinite(a.varianceOfMean));

  ExperimentScene eight = scene("{integrator: path, spp: 8, chunk_spp: 1}");
  ASSERT_EQ(referenceKey(four), referenceKey(eight)) << "the budget is not part of the key";
  Reference extended = obtain(eight, "extended");
  EXPECT_EQ(sidecar(eight, "extended")["chunks"].as<int>(), 8);
  Reference fresh = obtain(eight, "fresh");

  const float tolerance = 8 * std::ldexp(1.f, -24);
  double different = 0;
  for (size_t i = 0; i < fresh.image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      float x = extended.image.pixels[i][c], y = fresh.image.pixels[i][c];
      different += std::abs(x - y) > tolerance * std::max(std::abs(y), 1e-30f);
    }
  EXPECT_EQ(different, 0);
  EXPECT_NEAR(extended.varianceOfMean, fresh.varianceOfMean, 8 * std::ldexp(1.0, -24) * fresh.varianceOfMean);
  EXPECT_LT(fresh.varianceOfMean, a.varianceOfMean) << "twice the chunks, about half the variance";
}

// The variance image, from the spread across chunks, against its definition:
// two independent references A and B (different seeds) differ per pixel by
// E[(A − B)²] = var(A) + var(B). The per-pixel differences
// (A − B)² − (vA + vB) have mean 0; pixels are independent under path
// tracing, so their mean is tested against its standard error (|z| < 4).
TEST_F(ChunkedReference, ItsVarianceImagePredictsTheSpreadOfIndependentReferences) {
  // A diffuse floor filling the view under a large spherical light, direct
  // light only: every pixel's variance comes from sampling the light, of
  // similar size everywhere and light-tailed, so the standard error is small
  // enough that a variance 5 % off fails.
  std::ofstream(dir_ / "scene.yaml") << "camera: {position: [0, 2, 2], look_at: [0, 0, 0], fov: 30}\n"
                                        "film: {width: 128, height: 128}\n"
                                        "materials: {floor: {type: diffuse, albedo: 0.5}}\n"
                                        "shapes:\n"
                                        "  - {type: rectangle, material: floor, transform: {scale: 20, rotate_x: -90}}\n"
                                        "  - {type: sphere, material: none, center: [0, 3, 0], radius: 1.5, emission: 4}\n";
  const std::string spec = "{integrator: path, params: {max_depth: 2}, spp: 64, chunk_spp: 4, seed: ";
  ExperimentScene first = scene(spec + "11}", 128), second = scene(spec + "12}", 128);
  obtain(first, "results");
  obtain(second, "results");
  auto image = [&](const ExperimentScene& s, const std::string& suffix) {
    return readExr((dir_ / "results" / "references" / ("scene-" + referenceKey(s) + suffix)).string());
  };
  Image a = image(first, ".exr"), va = image(first, ".variance.exr");
  Image b = image(second, ".exr"), vb = image(second, ".variance.exr");

  double sum = 0, sumSq = 0, scale = 0;
  size_t n = 0;
  // One channel: the scene is grey, so the three are the same samples and
  // counting them thrice would understate the standard error by √3.
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    double diff = double(a.pixels[i].x) - double(b.pixels[i].x);
    double predicted = double(va.pixels[i].x) + double(vb.pixels[i].x);
    double d = diff * diff - predicted;
    sum += d, sumSq += d * d, scale += predicted, ++n;
  }
  double mean = sum / double(n), se = std::sqrt((sumSq / double(n) - mean * mean) / double(n - 1));
  ASSERT_GT(scale, 0);
  EXPECT_LT(std::abs(mean), 4 * se) << "mean difference " << mean << " (relative " << mean / (scale / double(n))
                                    << "), standard error " << se / (scale / double(n)) << " (relative)";
}

// A noise floor as the budget: chunks are added until the floor (√ of the
// mean variance of the mean) is at most the target, then the cache serves it.
TEST_F(ChunkedReference, ANoiseFloorBudgetStopsWhereItIsMet) {
  ExperimentScene probe = scene("{integrator: path, spp: 8, chunk_spp: 2}");
  double floorOfFour = std::sqrt(obtain(probe, "probe").varianceOfMean);
  double target = floorOfFour / 2;  // about four times the chunks
  std::ostringstream spec;
  spec.precision(17);
  spec << "{integrator: path, noise_floor: " << target << ", chunk_spp: 2}";
  ExperimentScene s = scene(spec.str());
  Reference r = obtain(s, "results");
  EXPECT_LE(std::sqrt(r.varianceOfMean), target);
  int chunks = sidecar(s, "results")["chunks"].as<int>();
  // Four chunks had twice the floor: about sixteen meet half of it (and
  // sixteen is the fewest a noise floor is trusted from).
  EXPECT_GE(chunks, 16);
  EXPECT_LE(chunks, 48);
  auto stamp = fs::last_write_time(dir_ / "results" / "references" / ("scene-" + referenceKey(s) + ".exr"));
  obtain(s, "results");
  EXPECT_EQ(sidecar(s, "results")["chunks"].as<int>(), chunks) << "a met budget renders nothing more";
  EXPECT_EQ(fs::last_write_time(dir_ / "results" / "references" / ("scene-" + referenceKey(s) + ".exr")), stamp);
}

TEST_F(ChunkedReference, ASecondsBudgetRendersAtLeastThatLong) {
  ExperimentScene s = scene("{integrator: path, seconds: 0.3, chunk_spp: 1}");
  obtain(s, "results");
  YAML::Node info = sidecar(s, "results");
  EXPECT_GE(info["seconds"].as<double>(), 0.3);
  EXPECT_GE(info["chunks"].as<int>(), 2);
}

// One process renders into a references folder at a time (the shipped
// experiments share references); a cached reference that meets its budget is
// read without the lock.
TEST_F(ChunkedReference, RenderingTakesTheReferencesFolderLock) {
  ExperimentScene s = scene("{integrator: path, spp: 4, chunk_spp: 2}");
  obtain(s, "results");
  RunLock held((dir_ / "results" / "references").string(), "other.yaml");
  EXPECT_NO_THROW(obtain(s, "results")) << "cached: no lock needed";
  ExperimentScene larger = scene("{integrator: path, spp: 8, chunk_spp: 2}");
  try {
    obtain(larger, "results");
    ADD_FAILURE() << "extended a reference while another process held the folder";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("references folder"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("in use by another lightbench process"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lb
