// A cached reference is keyed by the code its integrator compiles from (issue
// 39; cmake/render_source_hash.cmake, experiments/reference.cpp): a change to
// that code changes the key, so a stale reference cannot be served, and a
// change to another integrator does not, so long references stay usable. The
// hashing script runs here on a copy of core/ and integrators/, which the
// test edits as a developer would.
#include <gtest/gtest.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <unistd.h>
#include "experiments/reference.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

class IntegratorSourceHash : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lightbench-source-hash-" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    for (const char* sub : {"core", "integrators"})
      fs::copy(fs::path(LIGHTBENCH_SOURCE_DIR) / sub, dir_ / sub, fs::copy_options::recursive);
    fs::create_directories(dir_ / "experiments");
    for (const char* file : {"experiments/chunks.h", "experiments/chunks.cpp"})
      fs::copy(fs::path(LIGHTBENCH_SOURCE_DIR) / file, dir_ / file);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Every integrator folder's hash, as the build would compute it now.
  std::map<std::string, std::string> hashes() {
    std::string command = std::string("\"") + LIGHTBENCH_CMAKE_COMMAND + "\" -DSRC=" + dir_.string() +
                          " -DOUT=" + (dir_ / "h.h").string() + " -P " + LIGHTBENCH_SOURCE_DIR +
                          "/cmake/render_source_hash.cmake";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(dir_ / "h.h");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    std::map<std::string, std::string> out;
    std::regex entry("\\{\"([a-z_]+)\", \"([0-9a-f]{16})\"\\}");
    for (std::sregex_iterator it(s.begin(), s.end(), entry), end; it != end; ++it) out[(*it)[1]] = (*it)[2];
    return out;
  }
  void touch(const std::string& file) { std::ofstream(dir_ / file, std::ios::app) << "\n// edited\n"; }
  // Replaces the first `from` in `file` by `to`; false if there is none.
  bool edit(const std::string& file, const std::string& from, const std::string& to) {
    std::ifstream in(dir_ / file);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    size_t at = s.find(from);
    if (at == std::string::npos) return false;
    s.replace(at, from.size(), to);
    std::ofstream(dir_ / file, std::ios::trunc) << s;
    return true;
  }
  // Which integrators' hashes differ between two tables.
  static std::set<std::string> changed(const std::map<std::string, std::string>& a,
                                       const std::map<std::string, std::string>& b) {
    std::set<std::string> out;
    for (const auto& [name, hash] : a)
      if (b.at(name) != hash) out.insert(name);
    return out;
  }
  fs::path dir_;
};

TEST_F(IntegratorSourceHash, ChangesWithTheCodeItsIntegratorUsesAndOnlyThen) {
  auto before = hashes();
  for (const char* name : {"path", "light", "bdpt", "vcm", "photon", "sppm", "mlt", "guided", "direct"})
    ASSERT_TRUE(before.count(name)) << name;
  // An integrator's own estimator: only it.
  touch("integrators/light/light_tracer.cpp");
  auto afterLight = hashes();
  EXPECT_EQ(changed(before, afterLight), std::set<std::string>{"light"});
  // A shared module, header or implementation: every integrator that includes it.
  touch("integrators/bidirectional/connect.cpp");
  auto afterConnect = hashes();
  EXPECT_EQ(changed(afterLight, afterConnect), (std::set<std::string>{"bdpt", "bidirectional", "mlt", "vcm"}));
  touch("integrators/photon_map/photon_map.h");
  EXPECT_EQ(changed(afterConnect, hashes()),
            (std::set<std::string>{"irradiance_cache", "photon", "photon_map", "sppm", "vcm"}));
  // The core and the shared render loop: all of them.
  auto beforeCore = hashes();
  touch("core/bsdfs/diffuse.h");
  auto afterCore = hashes();
  EXPECT_EQ(changed(beforeCore, afterCore).size(), beforeCore.size());
  touch("integrators/render_loop.cpp");
  auto afterLoop = hashes();
  EXPECT_EQ(changed(afterCore, afterLoop).size(), beforeCore.size());
  // How a reference's seeded chunks are rendered and averaged: all of them.
  touch("experiments/chunks.cpp");
  auto afterChunks = hashes();
  EXPECT_EQ(changed(afterLoop, afterChunks).size(), beforeCore.size());
  // The registry names every integrator: a change outside the table (or to
  // the docs generated from it) changes no reference; a change to one entry
  // (how its settings are read, which configurations are unbiased) changes
  // that integrator's only.
  touch("integrators/registry.cpp");
  auto afterRegistry = hashes();
  EXPECT_TRUE(changed(afterChunks, afterRegistry).empty());
  ASSERT_TRUE(edit("integrators/registry.cpp", "p[\"mode\"].Scalar() == \"bpt\"", "p[\"mode\"].Scalar() == \"ppm\""));
  auto afterVcmEntry = hashes();
  EXPECT_EQ(changed(afterRegistry, afterVcmEntry), std::set<std::string>{"vcm"});
  ASSERT_TRUE(edit("integrators/registry.cpp", "PathTracerSettings::read(p)", "PathTracerSettings::read(p) "));
  EXPECT_EQ(changed(afterVcmEntry, hashes()), std::set<std::string>{"path"});
}

TEST(ReferenceKey, UsesItsIntegratorsSourceHash) {
  // This build's table: integrators that share no folder differ, and a name
  // with no folder falls back to the hash of all the rendering code.
  EXPECT_NE(integratorSourceHash("path"), integratorSourceHash("light"));
  EXPECT_NE(integratorSourceHash("bdpt"), integratorSourceHash("vcm"));
  EXPECT_EQ(integratorSourceHash("no_such_integrator"), renderSourceHash());
  EXPECT_EQ(integratorSourceHash("path").size(), 16u);
}

}  // namespace
}  // namespace lb
