// Issue 34, classes 6, 9 and 10 for run folders: state that is not what the
// runner wrote (a lock that is a directory, a log.csv of other bytes, a row
// torn before the last) is refused before anything renders, naming the file,
// and a scene file whose name has a space names its scene without the user
// being blamed for a `name` key never written.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include "core/image.h"
#include "experiments/run_lock.h"

namespace fs = std::filesystem;

namespace lb {
namespace {

std::string readFile(const fs::path& p) {
  std::stringstream ss;
  ss << std::ifstream(p, std::ios::binary).rdbuf();
  return ss.str();
}

class RunFolderState : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lightbench-state-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/cornell-box.yaml", dir_ / "my scene.yaml");
    writeExr((dir_ / "ref.exr").string(), Image(8, 8));
    std::ofstream(dir_ / "exp.yaml") << "scenes:\n"
                                        "  - scene: my scene.yaml\n"
                                        "    resolution: [8, 8]\n"
                                        "    reference: {file: ref.exr}\n"
                                        "configurations:\n"
                                        "  - {label: a, integrator: path}\n"
                                        "budget: {spp: 4}\n"
                                        "snapshots: {count: 2}\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  int run(const std::string& extra, std::string* err) {
    std::string cmd = std::string(LIGHTBENCH_BINARY) + " run " + (dir_ / "exp.yaml").string() + " --results " +
                      (dir_ / "results").string() + " --no-report --threads 1 " + extra + " 2>" +
                      (dir_ / "stderr.txt").string();
    int status = std::system(cmd.c_str());
    *err = readFile(dir_ / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // A finished run's folder.
  fs::path finishedRun() {
    std::string err;
    EXPECT_EQ(run("", &err), 0) << err;
    return *fs::directory_iterator(dir_ / "results" / "exp");
  }
  // --resume refused: exit 2, one line holding `phrase`, the folder as it was.
  void expectResumeRefused(const fs::path& runDir, const std::string& phrase) {
    std::map<std::string, std::string> before;
    for (const auto& f : fs::recursive_directory_iterator(runDir))  // the lock holds its holder's pid
      if (f.is_regular_file() && f.path().filename() != RunLock::FileName) before[f.path().string()] = readFile(f.path());
    std::string err;
    EXPECT_EQ(run("--resume", &err), 2) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find(phrase), std::string::npos) << err;
    std::map<std::string, std::string> after;
    for (const auto& f : fs::recursive_directory_iterator(runDir))
      if (f.is_regular_file() && f.path().filename() != RunLock::FileName) after[f.path().string()] = readFile(f.path());
    for (const auto& [file, bytes] : before)
      EXPECT_TRUE(after.count(file) && after[file] == bytes) << "the refused resume changed " << file;
    EXPECT_EQ(after.size(), before.size()) << "the refused resume added files";
  }
  fs::path dir_;
};

TEST_F(RunFolderState, SceneFileNameWithASpaceNamesTheScene) {
  fs::path runDir = finishedRun();
  EXPECT_TRUE(fs::exists(runDir / "my-scene__a.exr"));
}

TEST_F(RunFolderState, LockThatIsADirectoryIsRefusedBeforeRendering) {
  fs::path runDir = finishedRun();
  fs::remove(runDir / RunLock::FileName);
  fs::create_directory(runDir / RunLock::FileName);
  expectResumeRefused(runDir, "cannot open the lock file " + (runDir / RunLock::FileName).string());
}

// The pid went through a symbolic link named as the lock to whatever it
// named (an adversarial test overwrote /etc/passwd this way).
TEST_F(RunFolderState, LockThatIsASymbolicLinkIsRefusedAndItsTargetUntouched) {
  fs::path runDir = finishedRun();
  fs::path victim = runDir.parent_path() / "victim.txt";
  std::ofstream(victim) << "precious\n";
  fs::remove(runDir / RunLock::FileName);
  fs::create_symlink(victim, runDir / RunLock::FileName);
  expectResumeRefused(runDir, "cannot open the lock file " + (runDir / RunLock::FileName).string() +
                                  ": it is a symbolic link (remove it)");
  EXPECT_EQ(readFile(victim), "precious\n");
}

// A truncated meta.json was explained as "the experiment ... changed".
TEST_F(RunFolderState, ResumeOverATruncatedMetaJsonNamesIt) {
  fs::path runDir = finishedRun();
  std::string meta = readFile(runDir / "meta.json");
  std::ofstream(runDir / "meta.json", std::ios::trunc) << meta.substr(0, meta.size() / 2);
  expectResumeRefused(runDir, (runDir / "meta.json").string() + ": 'experiment_hash': not a run's metadata");
}

TEST_F(RunFolderState, ResumeOverALogThatIsADirectoryIsRefused) {
  fs::path runDir = finishedRun();
  fs::remove(runDir / "log.csv");
  fs::create_directory(runDir / "log.csv");
  expectResumeRefused(runDir, (runDir / "log.csv").string() + ": not a regular file");
}

TEST_F(RunFolderState, ResumeOverALogThatIsNotALogIsRefused) {
  fs::path runDir = finishedRun();
  std::ofstream(runDir / "log.csv", std::ios::binary) << std::string("\x8f\x01zq,\xff\n\x02\x03,,\n", 10);
  expectResumeRefused(runDir, (runDir / "log.csv").string() + ":1: not a lightbench log");
}

TEST_F(RunFolderState, ResumeOverARowTornBeforeTheLastIsRefused) {
  fs::path runDir = finishedRun();
  std::string log = readFile(runDir / "log.csv");
  size_t firstRow = log.find('\n') + 1;
  // The first row cut short, the rest intact: not what a killed run leaves.
  log.erase(firstRow + 10, log.find('\n', firstRow) - firstRow - 10);
  std::ofstream(runDir / "log.csv", std::ios::binary) << log;
  expectResumeRefused(runDir, (runDir / "log.csv").string() + ":2: a malformed row");
}

TEST_F(RunFolderState, ATornLastRowIsStillDroppedAndRedone) {
  fs::path runDir = finishedRun();
  std::string log = readFile(runDir / "log.csv");
  log.resize(log.size() - 3);  // the final row's end, as a kill mid-write leaves it
  std::ofstream(runDir / "log.csv", std::ios::binary) << log;
  std::string err;
  EXPECT_EQ(run("--resume", &err), 0) << err;
  std::string redone = readFile(runDir / "log.csv");
  EXPECT_EQ(redone.back(), '\n');
  EXPECT_EQ(std::count(redone.begin(), redone.end(), '\n'), 3) << redone;  // header and two snapshots
}

// Repeats alternate between the configurations, so that a machine's speed
// drifting over minutes is shared by all of them at equal time.
TEST_F(RunFolderState, ConfigurationsTakeTurnsRepeatByRepeat) {
  std::string exp = readFile(dir_ / "exp.yaml");
  exp.replace(exp.find("  - {label: a, integrator: path}\n"), 33,
              "  - {label: a, integrator: path}\n  - {label: b, integrator: light}\n");
  std::ofstream(dir_ / "exp.yaml") << exp << "repeats: 3\n";
  fs::path runDir = finishedRun();
  std::istringstream log(readFile(runDir / "log.csv"));
  std::string line, order;
  std::getline(log, line);
  while (std::getline(log, line))
    if (line.back() == '1') order += line.substr(line.find(',') + 1, 1);  // the label of each final row
  EXPECT_EQ(order, "ababab");
}

}  // namespace
}  // namespace lb
