#pragma once
// The fixture of the bad-input tests (tests/cli/bad_*_test.cpp): a scratch
// folder, a valid scene to break one line at a time, and the real
// `lightbench` binary run with its stderr captured.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace lb::testing {

namespace fs = std::filesystem;

struct RunResult {
  int exitCode;
  std::string err;
};

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lightbench-bad-input-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  RunResult render(const std::string& scene, const std::string& extra = "", const std::string& budget = "--spp 1") {
    std::string errFile = (dir_ / "stderr.txt").string();
    std::string cmd = "timeout 120 " + std::string(LIGHTBENCH_BINARY) + " render " + scene + " " + budget + " -q -o " +
                      (dir_ / "out" / "image.exr").string() + " " + extra + " 2>" + errFile;
    fs::create_directories(dir_ / "out");
    int status = std::system(cmd.c_str());
    std::stringstream ss;
    ss << std::ifstream(errFile).rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
  }
  // `lightbench <args>` as given (no -o, no budget added). A bad budget that
  // slipped through would render forever: the run is bounded (exit 124).
  RunResult run(const std::string& args) {
    std::string errFile = (dir_ / "stderr.txt").string();
    std::string cmd = "timeout 120 " + std::string(LIGHTBENCH_BINARY) + " " + args + " 2>" + errFile;
    fs::create_directories(dir_ / "out");
    int status = std::system(cmd.c_str());
    std::stringstream ss;
    ss << std::ifstream(errFile).rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
  }
  bool noOutput() const { return fs::is_empty(dir_ / "out"); }

  // A valid scene with one line replaced: the tests break it one way at a time.
  std::string scene(const std::string& shapeLine, const std::string& extraTop = "") {
    return "camera: {position: [0, 1, 4], look_at: [0, 1, 0]}\n"
           "film: {width: 8, height: 8}\n"
           "materials:\n"
           "  white: {type: diffuse, albedo: 0.7}\n" +
           extraTop +
           "shapes:\n"
           "  - {type: rectangle, material: white, transform: {rotate_x: -90}}\n" +
           shapeLine + "\n";
  }
  void expectError(const RunResult& r, const std::string& fileAndLine, const std::string& key,
                   const std::string& phrase) {
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find(fileAndLine), std::string::npos) << "missing location '" << fileAndLine << "' in: " << r.err;
    EXPECT_NE(r.err.find(key), std::string::npos) << "missing key '" << key << "' in: " << r.err;
    EXPECT_NE(r.err.find(phrase), std::string::npos) << "missing '" << phrase << "' in: " << r.err;
    EXPECT_TRUE(noOutput());
  }
  // A bad command-line value: exit 2, exactly one line naming the flag and
  // what is wrong, nothing written.
  void expectFlagError(const RunResult& r, const std::string& flag, const std::string& phrase) {
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not one line: " << r.err;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << "missing flag '" << flag << "' in: " << r.err;
    EXPECT_NE(r.err.find(phrase), std::string::npos) << "missing '" << phrase << "' in: " << r.err;
    EXPECT_TRUE(noOutput());
  }

  fs::path dir_;
};

}  // namespace lb::testing
