// Issue 12 on the experiment side: every bad input is one line naming file,
// line and key, exit code 2, and nothing written — checked before anything
// renders (a bad reference or crop used to fail minutes later, leaving a run
// folder behind). Also: reference EXRs with odd channels, experiment names
// that would escape --results, and one writer per run folder.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include "core/image.h"
#include "experiments/run_lock.h"
#include "experiments/runner.h"
#include "tests/support/render_helpers.h"

namespace fs = std::filesystem;

namespace lb {
namespace {

std::string readFile(const fs::path& p) {
  std::stringstream ss;
  ss << std::ifstream(p, std::ios::binary).rdbuf();
  return ss.str();
}

// Every file under `dir` with its bytes: "unchanged" means equal maps.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (f.is_regular_file()) files[fs::relative(f.path(), dir).string()] = readFile(f.path());
  return files;
}

// An EXR with the given float channels, each filled by `value(channel, pixel)`.
void writeChannels(const fs::path& path, int w, int h, const std::vector<std::string>& channels,
                   float (*value)(const std::string&, int)) {
  Imf::Header header(w, h);
  for (const auto& c : channels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  std::vector<std::vector<float>> data(channels.size(), std::vector<float>(size_t(w) * h));
  Imf::FrameBuffer fb;
  for (size_t c = 0; c < channels.size(); ++c) {
    for (int i = 0; i < w * h; ++i) data[c][i] = value(channels[c], i);
    fb.insert(channels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data[c].data()), sizeof(float),
                                      sizeof(float) * w));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(h);
}

class BadExperiment : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lightbench-bad-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/cornell-box.yaml", dir_ / "scene.yaml");
    writeExr((dir_ / "ref.exr").string(), Image(8, 8));
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Line numbers matter: the reference is on line 4, the crop on 5, the
  // second configuration on 8.
  std::string writeExperiment(const std::string& reference = "{file: ref.exr}",
                              const std::string& crop = "[0, 0, 8, 8]", const std::string& params = "{mis: power}",
                              const std::string& extra = "") {
    std::ofstream(dir_ / "exp.yaml") << "scenes:\n"
                                        "  - scene: scene.yaml\n"
                                        "    resolution: [8, 8]\n"
                                        "    reference: " << reference << "\n"
                                        "    crop: " << crop << "\n"
                                        "configurations:\n"
                                        "  - {label: a, integrator: path}\n"
                                        "  - {label: b, integrator: path, params: " << params << "}\n"
                                        "budget: {spp: 1}\n"
                                        "snapshots: {count: 1}\n" << extra;
    return (dir_ / "exp.yaml").string();
  }
  int runBinary(const std::string& args, std::string* err) {
    std::string cmd = std::string(LIGHTBENCH_BINARY) + " run " + args + " --no-report 2>" + (dir_ / "stderr.txt").string();
    int status = std::system(cmd.c_str());
    *err = readFile(dir_ / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // Runs the experiment expecting exit 2, exactly one line containing
  // `expected`, and no results folder at all.
  void expectRefused(const std::string& expected) {
    std::string err;
    fs::path results = dir_ / "results";
    EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + results.string(), &err), 2) << err;
    EXPECT_NE(err.find(expected), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "one line: " << err;
    EXPECT_FALSE(fs::exists(results)) << "a refused experiment wrote " << results;
  }
  fs::path dir_;
};

TEST_F(BadExperiment, BadReferenceFilesFailFirstAndLeaveNothing) {
  const std::string at = "exp.yaml:4: 'scenes[0].reference.file': ";
  writeExperiment();
  // Wrong resolution.
  writeExr((dir_ / "ref.exr").string(), Image(4, 4));
  expectRefused(at + "reference is 4×4, the scene renders 8×8");
  // Empty, corrupt and truncated files, and a directory.
  std::ofstream(dir_ / "ref.exr", std::ios::trunc).close();
  expectRefused(at + "cannot read");
  std::ofstream(dir_ / "ref.exr", std::ios::trunc) << std::string(4000, 'x');
  expectRefused(at + "cannot read");
  writeExr((dir_ / "ref.exr").string(), Image(8, 8));
  // Cut in the header, and in the pixels (the last bytes).
  fs::resize_file(dir_ / "ref.exr", fs::file_size(dir_ / "ref.exr") / 2);
  expectRefused(at + "cannot read");
  writeExr((dir_ / "ref.exr").string(), Image(8, 8));
  fs::resize_file(dir_ / "ref.exr", fs::file_size(dir_ / "ref.exr") - 8);
  expectRefused(at + "cannot read");
  fs::remove(dir_ / "ref.exr");
  fs::create_directory(dir_ / "ref.exr");
  expectRefused(at + "reference " + (dir_ / "ref.exr").string() + " is not a file");
}

TEST_F(BadExperiment, NonFiniteReferenceIsRefusedWithTheCount) {
  Image ref(8, 8);
  ref.at(1, 2) = Color(NAN, 0, 0);
  ref.at(3, 3) = Color(0, INFINITY, 0);
  ref.at(7, 7) = Color(0, 0, -INFINITY);
  writeExr((dir_ / "ref.exr").string(), ref);
  writeExperiment();
  expectRefused("exp.yaml:4: 'scenes[0].reference.file': reference " + (dir_ / "ref.exr").string() +
                " has 3 non-finite (NaN or Inf) pixels of 64");
}

TEST_F(BadExperiment, CropOutsideTheImageFailsBeforeTheReferenceRenders) {
  // A reference to render: the crop used to be checked only after it.
  writeExperiment("{integrator: path, spp: 1}", "[0, 0, 8, 9]");
  expectRefused("exp.yaml:5: 'scenes[0].crop': [0, 0, 8, 9] reaches beyond the 8×8 image of scene");
}

TEST_F(BadExperiment, ReferenceSceneAtAnotherResolutionFailsFirst) {
  // The reference scene keeps its own 256×256 film when the experiment gives
  // no resolution; the run's scene is made 8×8 in its own file.
  std::string s = readFile(dir_ / "scene.yaml");
  const std::string film = "film: {width: 256, height: 256}";
  ASSERT_NE(s.find(film), std::string::npos);
  s.replace(s.find(film), film.size(), "film: {width: 8, height: 8}");
  std::ofstream(dir_ / "small.yaml") << s;
  std::ofstream(dir_ / "exp.yaml") << "scenes:\n"
                                      "  - scene: small.yaml\n"
                                      "    reference: {scene: scene.yaml, spp: 1}\n"
                                      "configurations:\n"
                                      "  - {label: a, integrator: path}\n"
                                      "budget: {spp: 1}\n";
  expectRefused("exp.yaml:3: 'scenes[0].reference.scene': the reference scene renders 256×256, the scene renders 8×8");
}

TEST_F(BadExperiment, BrokenSceneFailsBeforeAnythingIsWritten) {
  std::ofstream(dir_ / "scene.yaml", std::ios::app) << "bogus_key: 1\n";
  writeExperiment("{integrator: path, spp: 1}");
  expectRefused("scene.yaml:");
  std::string err = readFile(dir_ / "stderr.txt");
  EXPECT_NE(err.find("'bogus_key': unknown key"), std::string::npos) << err;
}

// A path the system refuses (a file name over NAME_MAX) ended the run with a
// bare "filesystem error: status: File name too long" (found by
// fuzz_experiment in strict mode).
TEST_F(BadExperiment, AScenePathTheSystemRefusesNamesItsKey) {
  writeExperiment();
  std::string text = readFile(dir_ / "exp.yaml");
  text.replace(text.find("scene.yaml"), 10, std::string(300, 's') + ".yaml");
  std::ofstream(dir_ / "exp.yaml") << text;
  expectRefused("exp.yaml:2: 'scenes[0].scene': scene file not found: ");
  EXPECT_NE(readFile(dir_ / "stderr.txt").find("(File name too long)"), std::string::npos);
}

TEST_F(BadExperiment, ParameterErrorsNameTheirLine) {
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: powr}");
  expectRefused("exp.yaml:8: 'configurations[1].params.mis': unknown value 'powr'");
  writeExperiment("{integrator: path, params: {nee: maybe}, spp: 1}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.params.nee'");
}

// A metric given as a list used to end in yaml-cpp's "bad conversion", exit 1.
TEST_F(BadExperiment, AMetricThatIsNotANameIsRefused) {
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "metrics: [rmse, [relmse]]\n");
  expectRefused("exp.yaml:11: 'metrics': each metric is a name");
}

// A reference has one budget (issue 13), and each must be positive.
TEST_F(BadExperiment, AReferenceBudgetIsOneOfSppSecondsOrNoiseFloor) {
  writeExperiment("{integrator: path, spp: 64, seconds: 10}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.seconds': give one reference budget: spp, seconds or noise_floor");
  writeExperiment("{integrator: path, noise_floor: 0}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.noise_floor': must be > 0");
  writeExperiment("{integrator: path, seconds: -1}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.seconds': must be > 0");
  writeExperiment("{integrator: path, seconds: 1, chunk_spp: 0}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.chunk_spp': must be between 1 and 1048576");
}

// A corrupt cached reference sidecar (results/references/*.yaml) is named, not
// "bad conversion".
TEST_F(BadExperiment, ACorruptCachedReferenceSidecarIsNamed) {
  writeExperiment("{integrator: path, spp: 1}");
  std::string err;
  fs::path results = dir_ / "results";
  ASSERT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + results.string(), &err), 0) << err;
  fs::path sidecar;
  for (const auto& f : fs::directory_iterator(results / "references"))
    if (f.path().extension() == ".yaml") sidecar = f.path();
  ASSERT_FALSE(sidecar.empty());
  std::ofstream(sidecar, std::ios::app) << "variance_of_mean: [1]\n";
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + results.string(), &err), 2) << err;
  EXPECT_NE(err.find(sidecar.filename().string()), std::string::npos) << err;
  EXPECT_NE(err.find("variance_of_mean"), std::string::npos) << err;
}

// Issue 34, class 1: a reference whose per-pixel variance overflows a float
// (radiance of 1e22 at the lamp's edge: chunk values 0 or 1e22, squares
// 1e44) wrote +Inf into its cached variance image, and the comparisons'
// columns came out empty. Refused where it is computed, naming the
// reference's key and a pixel; no chunk of it is cached.
TEST_F(BadExperiment, AReferenceWhoseVarianceOverflowsIsRefused) {
  std::string scene = readFile(dir_ / "scene.yaml");
  std::ofstream(dir_ / "scene.yaml") << scene << "\n# a lamp too bright for its variance\n";
  std::ofstream(dir_ / "scene.yaml", std::ios::app)
      << "lights: [{type: point, position: [0, 1, 0], intensity: 1e22}]\n";
  writeExperiment("{integrator: path, spp: 4}");
  std::string err;
  fs::path results = dir_ / "results";
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + results.string(), &err), 2) << err;
  EXPECT_NE(err.find("exp.yaml:4: 'scenes[0].reference': reference scene: its per-pixel variance is beyond a float's range"),
            std::string::npos) << err;
  // Found while rendering: the reference's progress lines, then one error line, the last.
  size_t errorAt = err.find("error: ");
  EXPECT_NE(errorAt, std::string::npos) << err;
  EXPECT_TRUE(errorAt == 0 || err[errorAt - 1] == '\n') << err;
  EXPECT_EQ(err.find('\n', errorAt), err.size() - 1) << "the error is not the last line: " << err;
  if (fs::exists(results / "references")) {
    for (const auto& f : fs::directory_iterator(results / "references")) {
      EXPECT_NE(f.path().extension(), ".exr") << f.path();
    }
  }
}

// An unwritable --results used to fail with exit 1 and a filesystem error;
// /proc refuses new files even to root. A file in the way is not a folder.
TEST_F(BadExperiment, AnUnwritableResultsFolderIsRefusedBeforeRendering) {
  writeExperiment("{integrator: path, spp: 1}");
  std::string err;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results /proc/lightbench-results", &err), 2) << err;
  EXPECT_NE(err.find("command line: '--results': folder is not writable: /proc"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + (dir_ / "ref.exr" / "results").string(), &err), 2);
  EXPECT_NE(err.find("'--results': not a folder: " + (dir_ / "ref.exr").string()), std::string::npos) << err;
  // A file where the run's folder or the references folder would go was
  // found after the reference rendered (exit 1, a raw filesystem error).
  for (const char* taken : {"exp", "references"}) {
    fs::create_directories(dir_ / "taken");
    std::ofstream(dir_ / "taken" / taken) << "mine\n";
    EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + (dir_ / "taken").string(), &err), 2) << err;
    EXPECT_NE(err.find("'--results': " + (dir_ / "taken" / taken).string() + " is not a folder"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(readFile(dir_ / "taken" / taken), "mine\n");
    fs::remove_all(dir_ / "taken");
  }
}

// Found by hand (issue 12 walkthrough): each used to run, hang or fail late.
TEST_F(BadExperiment, OutOfRangeSettingsAreRefusedFirst) {
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "repeats: 1000000000\n");
  expectRefused("exp.yaml:11: 'repeats': must be in [1, 1000]");  // allocated gigabytes before
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "name: " + std::string(300, 'a') + "\n");
  expectRefused("exp.yaml:11: 'name': must be a plain folder name (not empty, at most 200 bytes");
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "name: \"a\\nb\"\n");
  expectRefused("exp.yaml:11: 'name': must be a plain folder name");
  std::string text = writeExperiment();
  std::string exp = readFile(text);
  exp.replace(exp.find("resolution: [8, 8]"), 18, "resolution: [1000000, 1000000]");
  std::ofstream(text) << exp;
  // Blamed the scene's film before; now beyond the largest image a run reads.
  expectRefused("exp.yaml:3: 'scenes[0].resolution': each must be from 1 to 8192");
  exp = readFile(text);
  exp.replace(exp.find("resolution: [1000000, 1000000]"), 30, "resolution: [8, 8]\n    world_scale: 1e30");
  std::ofstream(text) << exp;
  expectRefused("exp.yaml:4: 'scenes[0].world_scale': 1e+30 is outside [1e-4, 1e6]");
  // Issue 34: budgets that run forever, and seeds that meta.json and the log
  // would disagree on (-1 against 2^64 - 1).
  for (const char* budget : {"{seconds: 1e30}", "{seconds: -1}"}) {
    text = writeExperiment();
    exp = readFile(text);
    exp.replace(exp.find("budget: {spp: 1}"), 16, std::string("budget: ") + budget);
    std::ofstream(text) << exp;
    expectRefused("exp.yaml:9: 'budget.seconds': must be in [0, 30 days]");
  }
  text = writeExperiment();
  exp = readFile(text);
  exp.replace(exp.find("budget: {spp: 1}"), 16, "budget: {spp: -4}");
  std::ofstream(text) << exp;
  expectRefused("exp.yaml:9: 'budget.spp': must not be negative");
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "seed: -1\n");
  expectRefused("exp.yaml:11: 'seed': must not be negative");
  writeExperiment("{integrator: path, spp: 2, seed: -3}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.seed': must not be negative");
  // Beyond an int: said so, where it was "expected an integer, got 2147483648".
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "seed: 2147483648\n");
  expectRefused("exp.yaml:11: 'seed': must be a whole number in [-2147483648, 2147483647], got 2147483648");
}

// The verdict's keys (issue 32): each refusal names its line and key, and
// leaves nothing behind.
TEST_F(BadExperiment, VerdictKeysAreChecked) {
  struct Case {
    std::string extra, expected;
  };
  for (const Case& c : {
           Case{"rank_by: mape\n", "exp.yaml:11: 'rank_by': unknown metric 'mape' (a squared error: rmse, relmse"},
           Case{"rank_by: relmse_crop\nbaseline: c\n", "exp.yaml:12: 'baseline': no configuration is labelled 'c' (labels: 'a', 'b')"},
           Case{"confidence: 1.5\n", "exp.yaml:11: 'confidence': must be in [0.5, 0.9999]"},
           Case{"trim_fraction: 0.5\n", "exp.yaml:11: 'trim_fraction': must be in [0, 0.5)"},
           Case{"outlier_percentile: 99.9\n", "exp.yaml:11: 'outlier_percentile': was replaced by the relmse_trimmed metric"},
           Case{"repeats: {max: 8}\n", "'repeats.until_decided': a mapping asks for repeats until decided"},
           Case{"repeats: {until_decided: true, min: 1}\n", "'repeats.min': must be at least 2"},
           Case{"repeats: {until_decided: true, min: 4, max: 3}\n", "'repeats.max': must be in [min, 1000]"},
           Case{"repeats: {until_decided: true, maximum: 3}\n", "'repeats.maximum': unknown key"},
       }) {
    writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", c.extra);
    expectRefused(c.expected);
  }
  // A given reference's variance: a file that exists, of the reference's size,
  // and a chunk count only with it.
  writeExperiment("{file: ref.exr, variance: nowhere.exr}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.variance': reference variance image not found");
  writeExperiment("{file: ref.exr, chunks: 8}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.chunks': is the number of chunks of a `variance` image");
  writeExr((dir_ / "small.exr").string(), Image(4, 4));
  writeExperiment("{file: ref.exr, variance: small.exr, chunks: 8}");
  expectRefused("reference variance is 4×4, the reference 8×8");
  // A crop metric needs a crop in every scene.
  std::string text = readFile(writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "rank_by: rmse_crop\n"));
  text.replace(text.find("    crop: [0, 0, 8, 8]\n"), 22, "");
  std::ofstream(dir_ / "exp.yaml") << text;
  expectRefused("'rank_by': 'rmse_crop' needs a crop in every scene; scene 'scene' has none");
}

// A consistent integrator's bias would be in the reference (issue 13): it is
// refused unless the experiment says so; an unbiased VCM mode is fine.
TEST_F(BadExperiment, ABiasedReferenceIntegratorNeedsToBeAllowed) {
  writeExperiment("{integrator: sppm, spp: 1}");
  expectRefused("exp.yaml:4: 'scenes[0].reference.integrator': 'sppm' with these parameters is not unbiased");
  writeExperiment("{integrator: vcm, spp: 1}");
  expectRefused("'scenes[0].reference.integrator': 'vcm' with these parameters is not unbiased");
  for (const char* ok : {"{integrator: sppm, spp: 1, allow_biased_reference: true}",
                         "{integrator: vcm, params: {mode: bpt}, spp: 1}", "{integrator: bdpt, spp: 1}"})
    EXPECT_NO_THROW(loadExperiment(writeExperiment(ok), {})) << ok;
}

// Issue 34: a label names its configuration's files, <scene>__<slug>.*, so
// it may not be empty, be one of the run's own names (the reference, the
// plots) or make a name longer than the file system's 255 bytes; each is
// refused before anything renders. (runner_test.cpp derives the own names
// from the files a run writes.)
TEST_F(BadExperiment, LabelsThatWouldNameTheRunsOwnFilesAreRefused) {
  auto withLabel = [&](const std::string& label) {
    std::string text = readFile(writeExperiment());
    text.replace(text.find("label: a,"), 9, "label: '" + label + "',");
    std::ofstream(dir_ / "exp.yaml") << text;
  };
  for (const std::string label : {"reference", "Reference", "efficiency", "convergence", "sweep-radius"}) {
    withLabel(label);
    expectRefused("exp.yaml:7: 'configurations[0].label': label '" + label + "' would name its files");
  }
  withLabel("");
  expectRefused("exp.yaml:7: 'configurations[0].label': a label must not be empty");
  // The scene is named "scene": 255 - 5 - 2 - 29 (".", "__repeat1000.exr",
  // ".tmp-" and a pid of 7 digits) bytes are left.
  withLabel(std::string(220, 'L'));
  expectRefused("exp.yaml:7: 'configurations[0].label': label 'LLLLLLLLLLLLLLLLLLLLLLLL…' is 220 bytes: its files "
                "would have names of 256 bytes, over the file system's 255; with these scene names a label has at "
                "most 219 bytes");
  withLabel(std::string(219, 'L'));
  std::string err;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + (dir_ / "results").string(), &err), 0) << err;
}

// Issue 34, classes 4-7 beyond the labels: a scene name too long for the
// reference cache's file names (it failed after the first chunk, or was
// blamed on a label), one holding the "__" that separates scene and label in
// file names (scene cb's label x_repeat1 and scene cb__x's label repeat1), a
// resolution no reader of the run reads back, and an adaptive configuration
// whose spp ends within its uniform passes (it adapted nothing, silently).
TEST_F(BadExperiment, SceneNamesResolutionsAndAdaptiveBudgetsAreCheckedFirst) {
  auto edit = [&](const std::string& from, const std::string& to) {
    std::string text = readFile(writeExperiment());
    text.replace(text.find(from), from.size(), to);
    std::ofstream(dir_ / "exp.yaml") << text;
  };
  edit("    resolution: [8, 8]", "    name: " + std::string(101, 'n') + "\n    resolution: [8, 8]");
  expectRefused("exp.yaml:3: 'scenes[0].name': the scene's name 'nnnnnnnnnnnnnnnnnnnnnnnn…' is 101 bytes; at most 100");
  edit("    resolution: [8, 8]", "    name: " + std::string(100, 'n') + "\n    resolution: [8, 8]");
  std::string err;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + (dir_ / "results").string(), &err), 0) << err;
  fs::remove_all(dir_ / "results");
  edit("    resolution: [8, 8]", "    name: cb__x\n    resolution: [8, 8]");
  expectRefused("exp.yaml:3: 'scenes[0].name': the scene's name 'cb__x' holds \"__\"");
  edit("resolution: [8, 8]", "resolution: [8193, 8]");
  expectRefused("exp.yaml:3: 'scenes[0].resolution': each must be from 1 to 8192");
  edit("  - {label: a, integrator: path}", "  - {label: a, integrator: path, adaptive: {passes: 8}}");
  expectRefused("exp.yaml:9: 'budget.spp': 1 samples per pixel end within configuration 'a''s 8 uniform passes");
}

TEST_F(BadExperiment, AnExperimentThatIsNotARegularFileIsRefused) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo.yaml").c_str(), 0644), 0);
  std::string err;
  EXPECT_EQ(runBinary((dir_ / "fifo.yaml").string() + " --results " + (dir_ / "results").string(), &err), 2) << err;
  EXPECT_NE(err.find("fifo.yaml: not a regular file"), std::string::npos) << err;
}

TEST_F(BadExperiment, NamesThatWouldEscapeTheResultsFolderAreRefused) {
  // (Each would land inside this test's folder if accepted: results/../x is dir_/x.)
  fs::path outside = dir_ / "outside";
  for (std::string name : {outside.string(), std::string("../x"), std::string("\"\""), std::string("a/b"),
                           std::string("..")}) {
    writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "name: " + name + "\n");
    expectRefused("exp.yaml:11: 'name': must be a plain folder name");
    EXPECT_FALSE(fs::exists(outside)) << name;
    EXPECT_FALSE(fs::exists(dir_ / "x")) << name;
  }
  // A plain name is used as the run's folder.
  writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{mis: power}", "name: plain\n");
  std::string err;
  ASSERT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + (dir_ / "results").string(), &err), 0) << err;
  EXPECT_TRUE(fs::exists(dir_ / "results" / "plain"));
}

TEST_F(BadExperiment, ASecondWriterOfARunFolderIsRefused) {
  std::string exp = writeExperiment();
  fs::path results = dir_ / "results";
  std::string err;
  ASSERT_EQ(runBinary(exp + " --results " + results.string(), &err), 0) << err;
  fs::path run = *fs::directory_iterator(results / "exp");
  // This process plays the run still going: it holds the lock.
  int fd = ::open((run / RunLock::FileName).c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  std::string pid = std::to_string(getpid()) + "\n";
  ASSERT_EQ(::ftruncate(fd, 0), 0);
  ASSERT_EQ(::pwrite(fd, pid.data(), pid.size(), 0), ssize_t(pid.size()));
  auto before = snapshot(results);
  EXPECT_EQ(runBinary(exp + " --resume --results " + results.string(), &err), 2);
  EXPECT_NE(err.find("run folder " + run.string() + " is in use by another lightbench process (pid " +
                     std::to_string(getpid()) + ")"),
            std::string::npos)
      << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(snapshot(results), before) << "the refused process changed the run folder";
  ::close(fd);
  // Released (as when its process ends, even killed): the resume goes ahead.
  EXPECT_EQ(runBinary(exp + " --resume --results " + results.string(), &err), 0) << err;
  EXPECT_NE(err.find("already complete"), std::string::npos) << err;
}

TEST_F(BadExperiment, ARunThatFailsBeforeFinishingAnyRunLeavesNoFolder) {
  // Refused only once the scene is known (the photon map's memory check, at
  // preprocessing): 2e9 photon paths store ~1e10 photons, hundreds of GiB.
  std::string exp = writeExperiment("{file: ref.exr}", "[0, 0, 8, 8]", "{global_photons: 2000000000}");
  std::string text = readFile(exp);
  text.replace(text.find("label: b, integrator: path"), 26, "label: b, integrator: photon");
  text.replace(text.find("  - {label: a, integrator: path}\n"), 33, "");
  std::ofstream(exp) << text;
  std::string err;
  fs::path results = dir_ / "results";
  EXPECT_EQ(runBinary(exp + " --results " + results.string(), &err), 2) << err;
  EXPECT_NE(err.find("exp.yaml:7: 'configurations[0].params.global_photons': "), std::string::npos) << err;
  EXPECT_NE(err.find("request fewer photons"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(results / "exp")) << "the failed run left its folder";
}

float channelValue(const std::string& channel, int pixel) {
  if (channel.find("beauty") != std::string::npos) return 100;  // the layer that must not be read
  float base = channel.back() == 'R' ? 1 : channel.back() == 'G' ? 2 : channel.back() == 'B' ? 3 : 0.5f;
  return base + 0.01f * float(pixel);
}

TEST(ReadExr, GreyAndSingleLayerImagesAreReadNotBlack) {
  fs::path dir = fs::temp_directory_path() / ("lightbench-exr-" + std::to_string(getpid()));
  fs::create_directories(dir);
  writeChannels(dir / "y.exr", 4, 2, {"Y"}, channelValue);
  Image y = readExr((dir / "y.exr").string());
  ASSERT_EQ(y.width, 4);
  ASSERT_EQ(y.height, 2);
  for (int i = 0; i < 8; ++i) {
    float v = 0.5f + 0.01f * float(i);
    EXPECT_EQ(y.pixels[i], Color(v, v, v)) << i;
  }
  writeChannels(dir / "layer.exr", 4, 2, {"color.R", "color.G", "color.B", "depth.Z"}, channelValue);
  Image l = readExr((dir / "layer.exr").string());
  for (int i = 0; i < 8; ++i) EXPECT_EQ(l.pixels[i], Color(1, 2, 3) + Color(0.01f * float(i))) << i;
  // Plain R, G, B win over a layer's.
  writeChannels(dir / "both.exr", 4, 2, {"R", "G", "B", "beauty.R", "beauty.G", "beauty.B"}, channelValue);
  EXPECT_EQ(readExr((dir / "both.exr").string()).pixels[0], Color(1, 2, 3));

  // Ambiguous or colourless: refused, naming the channels found.
  auto message = [&](const char* file) {
    try {
      readExr((dir / file).string());
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  writeChannels(dir / "two.exr", 4, 2, {"a.R", "a.G", "a.B", "b.R", "b.G", "b.B"}, channelValue);
  EXPECT_NE(message("two.exr").find("several layers have R, G, B (a, b); found channels: a.B, a.G, a.R, b.B"),
            std::string::npos)
      << message("two.exr");
  writeChannels(dir / "z.exr", 4, 2, {"Z"}, channelValue);
  EXPECT_NE(message("z.exr").find("no R, G, B (or Y) channels; found: Z"), std::string::npos) << message("z.exr");
  writeChannels(dir / "rg.exr", 4, 2, {"R", "G"}, channelValue);
  EXPECT_NE(message("rg.exr").find("found: G, R"), std::string::npos) << message("rg.exr");
  fs::remove_all(dir);
}

// A header whose data window is far larger than any image lightbench reads is
// refused before the image is allocated (fuzz_exr found a 1.9 KB file claiming
// 1000000 × 200 pixels, and a 361-byte one that OpenEXR's core reader sees as
// small but its C++ reader as 711 million pixels): a file is written with such
// a header and no pixels; the fuzzer's file is read too.
TEST(ReadExr, AHugeDataWindowIsRefusedBeforeAllocating) {
  fs::path path = fs::temp_directory_path() / ("lightbench-exr-huge-" + std::to_string(getpid()) + ".exr");
  {
    Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i((1 << 22) - 1, (1 << 20) - 1));
    Imf::Header header(window, window);
    header.channels().insert("R", Imf::Channel(Imf::FLOAT));
    header.channels().insert("G", Imf::Channel(Imf::FLOAT));
    header.channels().insert("B", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);  // no pixels written: only the header and empty offsets
  }
  std::string message = "no error";
  try {
    readExr(path.string());
  } catch (const std::exception& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("data window (4194304 x 1048576 pixels) is larger than the 67108864 pixels"), std::string::npos)
      << message;
  fs::remove(path);
  message = "no error";
  try {
    readExr(test::sourcePath("tests/data/exr/claims-711M-pixels-in-361-bytes.exr"));
  } catch (const std::exception& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("is larger than the 67108864 pixels (8192 x 8192) lightbench reads"), std::string::npos)
      << message;
}

// A header declaring more pixels than its file can hold is refused from the
// header, before the image is allocated: fuzz_exr found this 361-byte file
// declaring 7563621 x 1 ZIP pixels (45 MB of data, which zlib cannot shrink
// more than 1032:1); reading it allocated 90 MB and took 8 s under ASan. The
// same check on a file cut short after its header (NO_COMPRESSION).
TEST(ReadExr, AHeaderDeclaringMorePixelsThanTheFileHoldsIsRefused) {
  auto message = [](const std::string& path) {
    try {
      readExr(path);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string fuzzed = message(test::sourcePath("tests/data/exr/zip-7563621x1-pixels-in-361-bytes.exr"));
  EXPECT_NE(fuzzed.find("declares 7563621 x 1 pixels, which need at least 87965 bytes, but the file has 361"),
            std::string::npos) << fuzzed;

  fs::path path = fs::temp_directory_path() / ("lightbench-exr-short-" + std::to_string(getpid()) + ".exr");
  {
    Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(999, 999));
    Imf::Header header(window, window);
    header.compression() = Imf::NO_COMPRESSION;
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::HALF));
    Imf::OutputFile file(path.c_str(), header);  // header and offset table only: 6 MB of pixels missing
  }
  std::string cut = message(path.string());
  EXPECT_NE(cut.find("declares 1000 x 1000 pixels, which need at least 6016000 bytes"), std::string::npos) << cut;
  fs::remove(path);
}

}  // namespace
}  // namespace lb
