// The experiment runner end to end on a tiny scene: log columns and
// monotonicity, images and report, reference caching, kill and resume, and
// bad experiment files (through the real binary).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include "experiments/reference.h"
#include "experiments/runner.h"

namespace fs = std::filesystem;

namespace lb {
namespace {

void expectMetaSchema(const nlohmann::json& m);  // below the test that uses it

std::string readFile(const fs::path& p) {
  std::stringstream ss;
  ss << std::ifstream(p).rdbuf();
  return ss.str();
}

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
};

CsvTable readCsv(const fs::path& p) {
  CsvTable t;
  std::ifstream in(p);
  std::string line;
  auto split = [](const std::string& l) {
    std::vector<std::string> f;
    std::string cur;
    bool q = false;
    for (char c : l) {
      if (c == '"') q = !q;
      else if (c == ',' && !q) f.push_back(cur), cur.clear();
      else cur += c;
    }
    f.push_back(cur);
    return f;
  };
  std::getline(in, line);
  t.header = split(line);
  while (std::getline(in, line)) {
    auto f = split(line);
    EXPECT_EQ(f.size(), t.header.size()) << "torn line: " << line;
    if (f.size() != t.header.size()) continue;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < f.size(); ++i) row[t.header[i]] = f[i];
    t.rows.push_back(row);
  }
  return t;
}

class Runner : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lightbench-runner-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/cornell-box.yaml", dir_ / "scene.yaml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string writeExperiment(const std::string& budget, int repeats = 2, const std::string& extra = "") {
    std::string text = "scenes:\n"
                       "  - scene: scene.yaml\n"
                       "    resolution: [16, 16]\n"
                       "    reference: {integrator: path, spp: 64}\n"
                       "    crop: [4, 8, 12, 16]\n"
                       "configurations:\n"
                       "  - {label: bsdf, integrator: path, params: {nee: false}}\n"
                       "  - {label: mis, integrator: path}\n"
                       "budget: " + budget + "\n"
                       "snapshots: {count: 4}\n"
                       "repeats: " + std::to_string(repeats) + "\n" + extra;
    std::ofstream(dir_ / "exp.yaml") << text;
    return (dir_ / "exp.yaml").string();
  }
  int runBinary(std::string args, std::string* err = nullptr) {
    if (args.find("--results") == std::string::npos) args += " --results " + (dir_ / "results-default").string();
    std::string cmd = std::string(LIGHTBENCH_BINARY) + " run " + args + " 2>" + (dir_ / "stderr.txt").string();
    int status = std::system(cmd.c_str());
    if (err) *err = readFile(dir_ / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path dir_;
};

TEST_F(Runner, WritesLogImagesPlotsAndReport) {
  Experiment e = loadExperiment(writeExperiment("{spp: 32}"), {});
  RunnerOptions o;
  o.resultsRoot = (dir_ / "results").string();
  fs::path run = runExperiment(e, o);

  CsvTable log = readCsv(run / "log.csv");
  std::vector<std::string> expected;
  for (size_t i = 0; LogColumns[i]; ++i) expected.push_back(LogColumns[i]);
  EXPECT_EQ(log.header, expected);

  // Per run: times and spp never decrease, exactly one final row; the error
  // falls on average (first snapshot vs final, over all runs).
  std::map<std::string, std::vector<std::map<std::string, std::string>>> runs;
  for (const auto& r : log.rows) runs[r.at("label") + "/" + r.at("repeat")].push_back(r);
  EXPECT_EQ(runs.size(), 4u);
  double firstErr = 0, lastErr = 0;
  for (const auto& [key, rows] : runs) {
    ASSERT_GE(rows.size(), 2u) << key;
    int finals = 0;
    for (size_t i = 0; i < rows.size(); ++i) {
      finals += rows[i].at("final") == "1";
      if (i) {
        EXPECT_GE(std::stod(rows[i].at("time_s")), std::stod(rows[i - 1].at("time_s"))) << key;
        EXPECT_GE(std::stoi(rows[i].at("spp")), std::stoi(rows[i - 1].at("spp"))) << key;
      }
    }
    EXPECT_EQ(finals, 1) << key;
    EXPECT_EQ(rows.back().at("spp"), "32") << key;
    EXPECT_FALSE(rows.back().at("rmse_crop").empty());
    firstErr += std::stod(rows.front().at("rmse"));
    lastErr += std::stod(rows.back().at("rmse"));
  }
  EXPECT_LT(lastErr, firstErr);

  for (const char* f : {"meta.json", "rmse_vs_time.png", "scene__rmse_vs_time.svg", "scene__rmse_vs_spp.png",
                        "scene__efficiency.png", "scene__reference.png", "scene__mis.exr", "scene__mis_error.png",
                        "scene__bsdf_crop.png", "report.html", "scene__mis__repeat1.exr", "decomposition.csv"})
    EXPECT_TRUE(fs::exists(run / f)) << f;
  // Two repeats: each configuration's final MSE split into bias² and variance
  // (experiments/decomposition.h), one row per configuration, shown in the report.
  // Its MSE is the mean over repeats of each run's final RMSE² in log.csv
  // (the same images, read back from their EXRs).
  CsvTable split = readCsv(run / "decomposition.csv");
  ASSERT_EQ(split.rows.size(), 2u);
  for (const auto& row : split.rows) {
    EXPECT_EQ(row.at("repeats"), "2");
    double mse = 0;
    for (const auto& r : log.rows)
      if (r.at("label") == row.at("label") && r.at("final") == "1") mse += std::pow(std::stod(r.at("rmse")), 2) / 2;
    EXPECT_NEAR(std::stod(row.at("mse")), mse, 1e-6 * mse) << row.at("label");
    EXPECT_GT(std::stod(row.at("variance")), 0);
    EXPECT_FALSE(row.at("reference_variance").empty()) << "a rendered reference's variance is known";
  }
  EXPECT_NE(readFile(run / "report.html").find("Final MSE split over the repeats"), std::string::npos);
  // The report embeds its images: every <img> is a data URI, and every
  // configuration appears with its image and error image.
  std::string report = readFile(run / "report.html");
  // (A plain scan: std::regex recurses per character and overflows on base64.)
  int images = 0;
  const std::string tag = "<img src='";
  for (size_t at = report.find(tag); at != std::string::npos; at = report.find(tag, at + 1), ++images)
    EXPECT_EQ(report.compare(at + tag.size(), 22, "data:image/png;base64,"), 0);
  EXPECT_EQ(images, 3 /* plots */ + 2 * (1 + 2 * 2) /* full and crop: reference + 2 × (image, error) */);
  for (const char* label : {"<figcaption>bsdf</figcaption>", "<figcaption>mis — error</figcaption>"})
    EXPECT_NE(report.find(label), std::string::npos) << label;
  expectMetaSchema(nlohmann::json::parse(readFile(run / "meta.json")));

  // Issue 34: no label may name its files like the run's own. A label whose
  // slug is L writes scene__L.exr, .png, _crop.png, _error.png and
  // _error_crop.png (and __repeatN.exr); each file of the run that is not a
  // configuration's and has that form for a valid slug L must make label L
  // refused. (The run's files are read here, not the code's list of names.)
  std::string text = readFile(dir_ / "exp.yaml");
  int collisions = 0;
  for (const auto& f : fs::directory_iterator(run)) {
    std::string name = f.path().filename().string();
    if (name.rfind("scene__", 0) != 0) continue;
    for (std::string suffix : {".exr", ".png", "_crop.png", "_error.png", "_error_crop.png"}) {
      if (name.size() <= 7 + suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix)) continue;
      std::string label = name.substr(7, name.size() - 7 - suffix.size());
      bool validSlug = std::all_of(label.begin(), label.end(), [](char c) { return std::islower(c) || std::isdigit(c) || c == '-'; });
      if (!validSlug || label == "bsdf" || label == "mis") continue;
      std::string t = text;
      t.replace(t.find("label: bsdf,"), 12, "label: " + label + ",");
      std::ofstream(dir_ / "own.yaml") << t;
      EXPECT_THROW(loadExperiment((dir_ / "own.yaml").string(), {}), std::exception) << name << " as label " << label;
      ++collisions;
    }
  }
  EXPECT_GE(collisions, 3) << "scene__reference.exr, .png and _crop.png at least";
}

// meta.json's schema (issue 15): real JSON, parameters as JSON values (not
// YAML text inside strings), every field a notebook relies on with its type.
void expectMetaSchema(const nlohmann::json& m) {
  using T = nlohmann::json::value_t;
  auto is = [](const nlohmann::json& j, const char* key, std::initializer_list<T> types) {
    ASSERT_TRUE(j.contains(key)) << key;
    bool ok = false;
    for (T t : types) ok = ok || j[key].type() == t || (t == T::number_float && j[key].is_number());
    EXPECT_TRUE(ok) << key << " is " << j[key].type_name();
  };
  for (const char* k : {"experiment", "experiment_file", "lightbench", "git_commit", "started", "experiment_hash"})
    is(m, k, {T::string});
  is(m, "finished", {T::string});  // null while running
  is(m, "machine", {T::object});
  is(m["machine"], "cores", {T::number_unsigned, T::number_integer});
  for (const char* k : {"threads_per_run", "jobs", "repeats"}) is(m, k, {T::number_unsigned, T::number_integer});
  is(m, "budget", {T::object});
  is(m["budget"], "seconds", {T::number_float});
  EXPECT_EQ(m["seeds"], nlohmann::json({1, 7920}));
  is(m, "metrics", {T::array});
  is(m, "relmse_epsilon", {T::number_float});
  is(m, "libraries", {T::object});
  is(m["libraries"], "embree", {T::string});
  is(m, "experiment_source", {T::object});
  ASSERT_TRUE(m["scenes"].is_array() && !m["scenes"].empty());
  for (const auto& s : m["scenes"]) {
    for (const char* k : {"name", "file", "reference", "reference_used", "reference_exr"}) is(s, k, {T::string});
    is(s, "reference_rmse_floor", {T::number_float, T::null});
    is(s, "crop", {T::array, T::null});
    is(s, "reference_integrator", {T::object, T::string});
  }
  ASSERT_TRUE(m["configurations"].is_array() && !m["configurations"].empty());
  for (const auto& c : m["configurations"]) {
    is(c, "label", {T::string});
    is(c, "integrator", {T::string});
    is(c, "unbiased", {T::boolean});
    is(c, "resolved_parameters", {T::object});
    // Values, typed: the path tracer's nee is a bool and max_depth a number.
    EXPECT_TRUE(c["resolved_parameters"]["nee"].is_boolean()) << c.dump();
    EXPECT_TRUE(c["resolved_parameters"]["max_depth"].is_number_integer()) << c.dump();
    EXPECT_TRUE(c["resolved_parameters"]["mis"].is_string()) << c.dump();
  }
}

TEST_F(Runner, ReportCopesWithOneRepeatAndUnevenSnapshots) {
  // One repeat (as --quick forces) and a budget that is not a power of two.
  Experiment e = loadExperiment(writeExperiment("{spp: 30}", 1), {});
  RunnerOptions o;
  o.resultsRoot = (dir_ / "results").string();
  fs::path run = runExperiment(e, o);
  EXPECT_TRUE(fs::exists(run / "report.html"));
  EXPECT_TRUE(fs::exists(run / "scene__rmse_vs_spp.png"));
}

std::vector<std::map<std::string, std::string>> rowsOf(const CsvTable& t, const std::string& key,
                                                      const std::string& value) {
  std::vector<std::map<std::string, std::string>> out;
  for (const auto& r : t.rows)
    if (r.at(key) == value) out.push_back(r);
  return out;
}

// Issue 32's acceptance on a tiny scene: two configurations that differ
// only in their label are tied (the same images: p = 1), a clearly worse one
// is ranked below them and decided, the verdict names its metric, and the
// report shows the rank groups with their intervals (no "no verdict" rule).
TEST_F(Runner, VerdictTiesTwoLabelsForOneConfigurationAndRanksTheRest) {
  std::string text = "scenes:\n"
                     "  - {scene: scene.yaml, resolution: [16, 16], reference: {integrator: path, spp: 256}}\n"
                     "configurations:\n"
                     "  - {label: mis, integrator: path}\n"
                     "  - {label: same again, integrator: path}\n"
                     "  - {label: bsdf only, integrator: path, params: {nee: false}}\n"
                     "budget: {spp: 16}\n"
                     "snapshots: {count: 2}\n"
                     "repeats: 4\n";
  std::ofstream(dir_ / "exp.yaml") << text;
  Experiment e = loadExperiment((dir_ / "exp.yaml").string(), {});
  RunnerOptions o;
  o.resultsRoot = (dir_ / "results").string();
  fs::path run = runExperiment(e, o);
  CsvTable verdict = readCsv(run / "verdict.csv");
  ASSERT_EQ(verdict.rows.size(), 3u);
  for (const char* column : {"scene", "label", "metric", "value", "ci_low", "ci_high", "rank_group", "decided"})
    EXPECT_NE(std::find(verdict.header.begin(), verdict.header.end(), column), verdict.header.end()) << column;
  auto row = [&](const std::string& label) { return rowsOf(verdict, "label", label).at(0); };
  EXPECT_EQ(row("mis").at("metric"), "relmse");  // the default ranking metric
  EXPECT_EQ(row("mis").at("rank_group"), "1-2");
  EXPECT_EQ(row("same again").at("rank_group"), "1-2");
  EXPECT_EQ(row("mis").at("decided"), "false");
  EXPECT_EQ(row("bsdf only").at("rank_group"), "3");
  EXPECT_EQ(row("bsdf only").at("decided"), "true");
  EXPECT_EQ(row("mis").at("value"), row("same again").at("value"));
  for (const auto& r : verdict.rows) {
    EXPECT_LE(std::stod(r.at("ci_low")), std::stod(r.at("value")));
    EXPECT_GE(std::stod(r.at("ci_high")), std::stod(r.at("value")));
  }
  CsvTable pairs = readCsv(run / "verdict_pairs.csv");
  bool twins = false;
  for (const auto& p : pairs.rows)
    if ((p.at("better") == "mis" || p.at("better") == "same again") &&
        (p.at("worse") == "mis" || p.at("worse") == "same again")) {
      twins = true;
      EXPECT_EQ(p.at("p"), "1");
      EXPECT_EQ(p.at("decided"), "false");
      EXPECT_NE(p.at("reason").find("identical"), std::string::npos);
    }
  EXPECT_TRUE(twins);
  std::string report = readFile(run / "report.html");
  EXPECT_NE(report.find("Ranked by <b>relMSE</b>, corrected"), std::string::npos);
  EXPECT_NE(report.find("<tr><td>1–2 (tied)</td><td>mis</td>"), std::string::npos);
  EXPECT_NE(report.find("<tr><td>3</td><td>bsdf only</td>"), std::string::npos);
  EXPECT_EQ(report.find("no verdict"), std::string::npos);
  EXPECT_TRUE(fs::exists(run / "scene__reference_variance.exr"));
  EXPECT_TRUE(fs::exists(run / "verdict_curves.csv"));
}

// repeats: {until_decided: true}: a look at 2 repeats cannot separate the
// path tracer's two MIS heuristics (near-identical estimators), so both get
// the schedule's next 4, where it ends and the verdict says why the pair is
// undecided; --resume finds everything done and renders nothing.
TEST_F(Runner, UntilDecidedAddsRepeatsToUndecidedPairsAndSaysWhy) {
  std::string text = "scenes:\n"
                     "  - {scene: scene.yaml, resolution: [16, 16], reference: {integrator: path, spp: 256}}\n"
                     "configurations:\n"
                     "  - {label: balance, integrator: path, params: {mis: balance}}\n"
                     "  - {label: power, integrator: path, params: {mis: power}}\n"
                     "budget: {spp: 8}\n"
                     "snapshots: {count: 1}\n"
                     "repeats: {until_decided: true, min: 2, max: 4}\n";
  std::ofstream(dir_ / "exp.yaml") << text;
  fs::path results = dir_ / "results";
  std::string err;
  ASSERT_EQ(runBinary((dir_ / "exp.yaml").string() + " --no-report --results " + results.string(), &err), 0) << err;
  EXPECT_NE(err.find("until decided: 4 more run(s)"), std::string::npos) << err;
  fs::path run = *fs::directory_iterator(results / "exp");
  CsvTable log = readCsv(run / "log.csv");
  std::map<std::string, int> finals;
  for (const auto& r : log.rows) finals[r.at("label")] += r.at("final") == "1";
  EXPECT_EQ(finals["balance"], 4);
  EXPECT_EQ(finals["power"], 4);
  CsvTable pairs = readCsv(run / "verdict_pairs.csv");
  ASSERT_EQ(pairs.rows.size(), 1u);
  EXPECT_EQ(pairs.rows[0].at("decided"), "false");
  EXPECT_NE(pairs.rows[0].at("reason").find("maximum of 4 repeats"), std::string::npos) << pairs.rows[0].at("reason");
  EXPECT_NE(err.find("undecided: "), std::string::npos) << err;
  nlohmann::json meta = nlohmann::json::parse(readFile(run / "meta.json"));
  EXPECT_EQ(meta["verdict"]["looks"], 2);
  ASSERT_EQ(runBinary((dir_ / "exp.yaml").string() + " --resume --no-report --results " + results.string(), &err), 0)
      << err;
  EXPECT_NE(err.find("resume: 4 of 4 runs already complete"), std::string::npos) << err;
  EXPECT_EQ(err.find("[run "), std::string::npos) << "nothing is rendered again";
  EXPECT_EQ(readCsv(run / "verdict_pairs.csv").rows[0].at("p"), pairs.rows[0].at("p"));

  // Configurations far apart are decided at the first look: no run is added.
  std::ofstream(dir_ / "far.yaml") << "scenes:\n"
                                      "  - {scene: scene.yaml, resolution: [16, 16], reference: {integrator: path, spp: 256}}\n"
                                      "configurations:\n"
                                      "  - {label: nee, integrator: path}\n"
                                      "  - {label: no nee, integrator: path, params: {nee: false}}\n"
                                      "budget: {spp: 16}\n"
                                      "snapshots: {count: 1}\n"
                                      "repeats: {until_decided: true, min: 4, max: 16}\n";
  ASSERT_EQ(runBinary((dir_ / "far.yaml").string() + " --no-report --results " + results.string(), &err), 0) << err;
  EXPECT_EQ(err.find("until decided:"), std::string::npos) << err;
  EXPECT_EQ(err.find("undecided: "), std::string::npos) << err;
}

// A given reference with its variance (a cached one's files, or one rendered
// elsewhere) corrects the errors exactly as the rendered one does: the same
// verdict, value for value.
TEST_F(Runner, AGivenReferenceWithItsVarianceCorrectsAsTheRenderedOne) {
  const std::string scenes = "scenes:\n  - {scene: scene.yaml, resolution: [16, 16], reference: ";
  const std::string rest = "}}\nconfigurations:\n  - {label: mis, integrator: path}\n  - {label: bsdf, integrator: path, "
                           "params: {nee: false}}\nbudget: {spp: 8}\nsnapshots: {count: 1}\nrepeats: 3\n";
  std::ofstream(dir_ / "rendered.yaml") << scenes << "{integrator: path, spp: 64" << rest;
  RunnerOptions o;
  o.resultsRoot = (dir_ / "results").string();
  o.report = false;
  Experiment rendered = loadExperiment((dir_ / "rendered.yaml").string(), {});
  fs::path a = runExperiment(rendered, o);
  std::string stem = (dir_ / "results" / "references" / ("scene-" + referenceKey(rendered.scenes[0]))).string();
  std::ofstream(dir_ / "given.yaml") << scenes << "{file: " << stem << ".exr, variance: " << stem
                                     << ".variance.exr, chunks: 8" << rest;
  // The cached reference's chunk count, as its sidecar records it.
  YAML::Node sidecar = YAML::LoadFile(stem + ".yaml");
  std::string text = readFile(dir_ / "given.yaml");
  text.replace(text.find("chunks: 8"), 9, "chunks: " + sidecar["chunks"].as<std::string>());
  std::ofstream(dir_ / "given.yaml") << text;
  fs::path b = runExperiment(loadExperiment((dir_ / "given.yaml").string(), {}), o);
  CsvTable va = readCsv(a / "verdict.csv"), vb = readCsv(b / "verdict.csv");
  ASSERT_EQ(va.rows.size(), vb.rows.size());
  for (size_t i = 0; i < va.rows.size(); ++i)
    for (const char* column : {"label", "value", "ci_low", "ci_high", "rank_group"})
      EXPECT_EQ(va.rows[i].at(column), vb.rows[i].at(column)) << column;
  nlohmann::json meta = nlohmann::json::parse(readFile(b / "meta.json"));
  EXPECT_EQ(meta["scenes"][0]["reference_chunks"], sidecar["chunks"].as<int>());
  // A given reference cannot be extended.
  std::ofstream(dir_ / "given.yaml", std::ios::app) << "";
  text = readFile(dir_ / "given.yaml");
  text.replace(text.find("repeats: 3"), 10, "repeats: {until_decided: true, extend_reference: true}");
  std::ofstream(dir_ / "given.yaml") << text;
  std::string err;
  EXPECT_EQ(runBinary((dir_ / "given.yaml").string(), &err), 2);
  EXPECT_NE(err.find("has a given reference (file), which cannot be extended"), std::string::npos) << err;
}

TEST_F(Runner, ReferenceKeyChangesWithSceneAndMesh) {
  std::ofstream(dir_ / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir_ / "scene.yaml", std::ios::app) << "\n";  // keep the copied scene valid
  {
    std::string s = readFile(dir_ / "scene.yaml");
    s.replace(s.find("shapes:\n"), 8, "shapes:\n  - {type: mesh, file: tri.obj}\n");
    std::ofstream(dir_ / "scene.yaml") << s;
  }
  Experiment e = loadExperiment(writeExperiment("{spp: 4}"), {});
  std::string k0 = referenceKey(e.scenes[0]);
  EXPECT_EQ(k0, referenceKey(e.scenes[0]));  // stable
  std::ofstream(dir_ / "tri.obj", std::ios::app) << "# edited\n";
  std::string k1 = referenceKey(e.scenes[0]);
  EXPECT_NE(k1, k0) << "a mesh edit must invalidate the reference";
  std::ofstream(dir_ / "scene.yaml", std::ios::app) << "# edited\n";
  std::string k2 = referenceKey(e.scenes[0]);
  EXPECT_NE(k2, k1) << "a scene edit must invalidate the reference";
  e.scenes[0].reference.chunkSpp += 1;
  EXPECT_NE(referenceKey(e.scenes[0]), k2) << "other reference settings must too";
  e.scenes[0].reference.chunkSpp -= 1;
  e.scenes[0].reference.spp *= 4;
  EXPECT_EQ(referenceKey(e.scenes[0]), k2) << "the budget must not: a larger one extends the cached chunks";

  // And the cache is used: a second run finds the file the first one wrote.
  Experiment small = loadExperiment(writeExperiment("{spp: 2}", 1), {});
  RunnerOptions o;
  o.resultsRoot = (dir_ / "results").string();
  o.report = false;
  runExperiment(small, o);
  fs::path cached = dir_ / "results" / "references" / ("scene-" + referenceKey(small.scenes[0]) + ".exr");
  EXPECT_TRUE(fs::exists(cached));
  auto stamp = fs::last_write_time(cached);
  runExperiment(small, o);
  EXPECT_EQ(fs::last_write_time(cached), stamp);
}

TEST_F(Runner, KilledRunKeepsItsLogAndResumeCompletesIt) {
  std::string exp = writeExperiment("{seconds: 3.0}", 2);
  fs::path results = dir_ / "results";
  pid_t pid = fork();
  if (pid == 0) {
    std::string out = (dir_ / "first.txt").string();
    freopen(out.c_str(), "w", stderr);
    execl(LIGHTBENCH_BINARY, LIGHTBENCH_BINARY, "run", exp.c_str(), "--results", results.c_str(), "--no-report",
          (char*)nullptr);
    _exit(127);
  }
  // Kill it after its first run finished and before the last one does.
  fs::path log;
  for (int i = 0; i < 600; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (log.empty() && fs::exists(results / "exp"))
      for (const auto& d : fs::directory_iterator(results / "exp")) log = d.path() / "log.csv";
    if (!log.empty() && fs::exists(log) && readFile(log).find(",1\n") != std::string::npos) break;
  }
  kill(pid, SIGKILL);
  int status;
  waitpid(pid, &status, 0);
  ASSERT_FALSE(log.empty());
  CsvTable partial = readCsv(log);  // readable: every complete line parses
  int finalsBefore = 0;
  for (const auto& r : partial.rows) finalsBefore += r.at("final") == "1";
  ASSERT_GE(finalsBefore, 1);
  ASSERT_LT(finalsBefore, 4) << "the run finished before it could be killed";

  std::string err;
  ASSERT_EQ(runBinary(exp + " --resume --no-report --results " + results.string(), &err), 0) << err;
  EXPECT_NE(err.find("already complete"), std::string::npos) << err;
  CsvTable full = readCsv(log);
  std::map<std::string, int> finals;
  std::map<std::string, std::vector<int>> spp;
  for (const auto& r : full.rows) {
    if (r.at("final") == "1") finals[r.at("label") + "/" + r.at("repeat")] += 1;
    spp[r.at("label") + "/" + r.at("repeat")].push_back(std::stoi(r.at("spp")));
  }
  EXPECT_EQ(finals.size(), 4u);
  for (const auto& [k, n] : finals) EXPECT_EQ(n, 1) << k;
  // The interrupted run's partial rows are gone: each run's snapshots are one
  // strictly increasing sequence of at most snapshots + 1 rows.
  for (const auto& [k, v] : spp) {
    EXPECT_LE(v.size(), 5u) << k;
    for (size_t i = 1; i < v.size(); ++i) EXPECT_GT(v[i], v[i - 1]) << k;
  }
  for (const char* f : {"scene__bsdf.exr", "scene__mis.exr", "scene__mis_error.png"})
    EXPECT_TRUE(fs::exists(log.parent_path() / f)) << f;

  // A changed experiment is not resumed into the old run.
  std::ofstream(dir_ / "exp.yaml", std::ios::app) << "seed: 5\n";
  EXPECT_EQ(runBinary(exp + " --resume --no-report --results " + results.string(), &err), 2);
  EXPECT_NE(err.find("changed since"), std::string::npos) << err;
}

// A log written before the host, cpu and threads columns (issue 19) is
// resumed by column name: its finished runs are kept, not silently dropped
// for having fewer columns, and only the unfinished run is redone.
TEST_F(Runner, ResumeKeepsTheRunsOfALogWithOlderColumns) {
  std::string exp = writeExperiment("{spp: 4}", 2);
  fs::path results = dir_ / "results";
  std::string err;
  ASSERT_EQ(runBinary(exp + " --no-report --results " + results.string(), &err), 0) << err;
  fs::path log;
  for (const auto& d : fs::directory_iterator(results / "exp")) log = d.path() / "log.csv";
  CsvTable table = readCsv(log);
  // The old format: without the three columns, and the last run unfinished.
  std::vector<std::string> old;
  int oldRows = 0;  // the three finished runs' rows
  for (const auto& r : table.rows) oldRows += !(r.at("label") == "mis" && r.at("repeat") == "1");
  for (const auto& c : table.header)
    if (c != "host" && c != "cpu" && c != "threads") old.push_back(c);
  std::ostringstream text;
  for (size_t i = 0; i < old.size(); ++i) text << (i ? "," : "") << old[i];
  text << "\n";
  for (const auto& r : table.rows) {
    if (r.at("label") == "mis" && r.at("repeat") == "1" && r.at("final") == "1") continue;
    for (size_t i = 0; i < old.size(); ++i) text << (i ? "," : "") << r.at(old[i]);
    text << "\n";
  }
  std::ofstream(log) << text.str();

  ASSERT_EQ(runBinary(exp + " --resume --no-report --results " + results.string(), &err), 0) << err;
  EXPECT_NE(err.find("resume: 3 of 4 runs already complete"), std::string::npos) << err;
  CsvTable resumed = readCsv(log);
  EXPECT_EQ(resumed.header, table.header);
  int finals = 0, carried = 0;
  for (const auto& r : resumed.rows) {
    finals += r.at("final") == "1";
    carried += r.at("host").empty();
  }
  EXPECT_EQ(finals, 4);
  EXPECT_EQ(carried, oldRows);  // carried over, their new columns empty
}

TEST_F(Runner, ScenesCanBeNamedScaledAndJudgedAgainstAnotherScene) {
  std::string text = "scenes:\n"
                     "  - {scene: scene.yaml, resolution: [16, 16], reference: {spp: 16}}\n"
                     "  - {scene: scene.yaml, name: tiny, world_scale: 1e-3, resolution: [16, 16],\n"
                     "     reference: {scene: scene.yaml, spp: 16}}\n"
                     "configurations:\n"
                     "  - {label: mis, integrator: path}\n"
                     "budget: {spp: 2}\n"
                     "snapshots: {count: 1}\n";
  std::ofstream(dir_ / "exp.yaml") << text;
  std::string err;
  fs::path results = dir_ / "r";
  ASSERT_EQ(runBinary((dir_ / "exp.yaml").string() + " --no-report --results " + results.string(), &err), 0) << err;
  // Both scenes are judged against one reference, rendered once from the unscaled scene.
  int references = 0;
  for (const auto& entry : fs::directory_iterator(results / "references"))
    references += entry.path().extension() == ".exr" && entry.path().stem().extension() != ".variance";
  EXPECT_EQ(references, 1);
  fs::path run = *fs::directory_iterator(results / "exp");
  CsvTable log = readCsv(run / "log.csv");
  std::set<std::string> scenes;
  for (const auto& row : log.rows) scenes.insert(row.at("scene"));
  EXPECT_EQ(scenes, (std::set<std::string>{"scene", "tiny"}));
  // Bad uses: a repeated name, a non-positive scale, a missing reference scene.
  for (auto [entry, phrase] : {std::pair{"  - {scene: scene.yaml, resolution: [16, 16]}\n", "two scenes are named 'scene'"},
                               std::pair{"  - {scene: scene.yaml, name: z, world_scale: 0}\n", "world_scale': must be positive"},
                               std::pair{"  - {scene: scene.yaml, name: z, reference: {scene: nowhere.yaml}}\n", "reference scene not found"}}) {
    std::string bad = text;
    bad.insert(bad.find("configurations:"), entry);
    std::ofstream(dir_ / "exp.yaml") << bad;
    EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2) << phrase;
    EXPECT_NE(err.find(phrase), std::string::npos) << err;
  }
}

TEST_F(Runner, BadExperimentFilesAreClearErrors) {
  struct Case {
    std::string extra, where, phrase;
  };
  std::string err;
  // Unknown top-level key.
  writeExperiment("{spp: 2}", 1, "snapshot: {count: 2}\n");
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2);
  EXPECT_NE(err.find("exp.yaml:12: 'snapshot': unknown key; did you mean 'snapshots'?"), std::string::npos) << err;
  // An integrator that is not built: named, fatal; skipped with a warning under --quick.
  std::string text = readFile(dir_ / "exp.yaml");
  text.replace(text.find("snapshot: {count: 2}\n"), 21, "");
  // (An integrator no issue plans, so this stays "not built".)
  text.replace(text.find("  - {label: mis, integrator: path}"), 34, "  - {label: later, integrator: radiosity}");
  std::ofstream(dir_ / "exp.yaml") << text;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2);
  EXPECT_NE(err.find("exp.yaml:8: 'configurations[1].integrator': integrator 'radiosity' is not built"), std::string::npos) << err;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --quick --no-report --results " + (dir_ / "r").string(), &err), 0) << err;
  EXPECT_NE(err.find("warning"), std::string::npos);
  EXPECT_NE(err.find("'radiosity' is not built"), std::string::npos);
  // Unknown integrator parameter, missing scene, bad budget.
  writeExperiment("{spp: 2}", 1);
  text = readFile(dir_ / "exp.yaml");
  text.replace(text.find("params: {nee: false}"), 20, "params: {nea: false}");
  std::ofstream(dir_ / "exp.yaml") << text;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2);
  EXPECT_NE(err.find("'configurations[0].params.nea': unknown key; did you mean 'nee'?"), std::string::npos) << err;
  writeExperiment("{}", 1);
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2);
  EXPECT_NE(err.find("'budget': needs seconds > 0 and/or spp > 0"), std::string::npos) << err;
  text = readFile(dir_ / "exp.yaml");
  text.replace(text.find("scene: scene.yaml"), 17, "scene: nowhere.yaml");
  std::ofstream(dir_ / "exp.yaml") << text;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2);
  EXPECT_NE(err.find("exp.yaml:2: 'scenes[0].scene': scene file not found"), std::string::npos) << err;
  // A crop beyond the image, and labels that would share file names.
  writeExperiment("{spp: 2}", 1);
  text = readFile(dir_ / "exp.yaml");
  text.replace(text.find("crop: [4, 8, 12, 16]"), 20, "crop: [4, 8, 12, 17]");
  std::ofstream(dir_ / "exp.yaml") << text;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string() + " --results " + (dir_ / "r2").string(), &err), 2);
  EXPECT_NE(err.find("exp.yaml:5: 'scenes[0].crop': [4, 8, 12, 17] reaches beyond the 16×16 image of scene"),
            std::string::npos)
      << err;
  writeExperiment("{spp: 2}", 1);
  text = readFile(dir_ / "exp.yaml");
  text.replace(text.find("label: mis,"), 11, "label: BSDF,");
  std::ofstream(dir_ / "exp.yaml") << text;
  EXPECT_EQ(runBinary((dir_ / "exp.yaml").string(), &err), 2);
  EXPECT_NE(err.find("label 'BSDF' collides with 'bsdf'"), std::string::npos) << err;
}

// `denoise: nlmeans`: every snapshot is also filtered and logged as its own
// configuration, at the same spp and a later time (the render's plus the
// features' and the filter's), marked biased in meta.json, with its images;
// the raw run's rows are unchanged. Integrators without a per-pixel variance
// (MLT's correlated passes) and unknown filters are refused, naming the key.
TEST_F(Runner, DenoisedSnapshotsAreLoggedBesideTheRawOnes) {
  std::string text = "scenes:\n"
                     "  - scene: scene.yaml\n"
                     "    resolution: [16, 16]\n"
                     "    reference: {integrator: path, spp: 64}\n"
                     "configurations:\n"
                     "  - {label: mis, integrator: path, denoise: nlmeans}\n"
                     "budget: {spp: 16}\n"
                     "snapshots: {count: 4}\n";
  std::ofstream(dir_ / "exp.yaml") << text;
  Experiment e = loadExperiment((dir_ / "exp.yaml").string(), {});
  RunnerOptions o;
  o.resultsRoot = (dir_ / "results").string();
  fs::path run = runExperiment(e, o);
  CsvTable log = readCsv(run / "log.csv");
  std::vector<std::map<std::string, std::string>> raw, denoised;
  for (const auto& r : log.rows) (r.at("label") == "mis" ? raw : denoised).push_back(r);
  ASSERT_EQ(raw.size(), 4u);
  ASSERT_EQ(denoised.size(), raw.size());
  for (size_t i = 0; i < raw.size(); ++i) {
    EXPECT_EQ(denoised[i].at("label"), "mis + nlmeans");
    EXPECT_EQ(denoised[i].at("spp"), raw[i].at("spp"));
    EXPECT_EQ(denoised[i].at("final"), raw[i].at("final"));
    EXPECT_GT(std::stod(denoised[i].at("time_s")), std::stod(raw[i].at("time_s")));
    EXPECT_TRUE(std::isfinite(std::stod(denoised[i].at("rmse"))));
    EXPECT_NE(denoised[i].at("rmse"), raw[i].at("rmse"));
  }
  // The same experiment without the filter: the raw rows' errors are the same.
  std::string plain = text;
  plain.replace(plain.find(", denoise: nlmeans"), std::string(", denoise: nlmeans").size(), "");
  std::ofstream(dir_ / "plain.yaml") << plain;
  Experiment p = loadExperiment((dir_ / "plain.yaml").string(), {});
  CsvTable plainLog = readCsv(fs::path(runExperiment(p, o)) / "log.csv");
  ASSERT_EQ(plainLog.rows.size(), raw.size());
  for (size_t i = 0; i < raw.size(); ++i) {
    EXPECT_EQ(plainLog.rows[i].at("rmse"), raw[i].at("rmse"));
    EXPECT_EQ(plainLog.rows[i].at("spp"), raw[i].at("spp"));
  }
  EXPECT_TRUE(fs::exists(run / "scene__mis---nlmeans.png"));
  nlohmann::json meta = nlohmann::json::parse(readFile(run / "meta.json"));
  bool found = false;
  for (const auto& c : meta["configurations"])
    if (c["label"] == "mis + nlmeans") {
      found = true;
      EXPECT_EQ(c["unbiased"], false);
    }
  EXPECT_TRUE(found);

  for (const char* bad : {"  - {label: m, integrator: mlt, denoise: nlmeans}\n",
                          "  - {label: m, integrator: path, denoise: nfor}\n"}) {
    std::string t = text;
    t.replace(t.find("  - {label: mis"), std::string("  - {label: mis, integrator: path, denoise: nlmeans}\n").size(), bad);
    std::ofstream(dir_ / "bad.yaml") << t;
    std::string err;
    EXPECT_EQ(runBinary((dir_ / "bad.yaml").string(), &err), 2) << bad;
    EXPECT_NE(err.find("denoise"), std::string::npos) << err;
  }
}

}  // namespace
}  // namespace lb
