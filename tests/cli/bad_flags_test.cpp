// Every bad command-line value is one line naming the flag, exit code 2, and
// no output file (issue 12). These run the real `lightbench` binary; the
// values are the ones that used to render forever, render the default, or
// wrap around silently.
#include <sys/stat.h>
#include "tests/support/bad_input_fixture.h"

namespace {

namespace fs = std::filesystem;
using lb::testing::BadInput;
using lb::testing::RunResult;

class BadFlag : public BadInput {
 protected:
  std::string validScene() {
    return write("s.yaml", scene("  - {type: sphere, center: [0, 1, 0], radius: 0.5, emission: 2}"));
  }
  // `render` of a valid 8x8 scene with `args`.
  RunResult renderWith(const std::string& args) {
    return run("render " + validScene() + " -q -o " + (dir_ / "out" / "image.exr").string() + " " + args);
  }
};

TEST_F(BadFlag, SppAndTimeMustBePositiveAndFinite) {
  for (const char* v : {"-1", "0", "1.5", "0x10", "18446744073709551616"}) {
    SCOPED_TRACE(v);
    expectFlagError(renderWith(std::string("--spp ") + v), "--spp", std::string("got '") + v + "'");
  }
  for (const char* v : {"-1", "0", "nan", "inf", "-inf", "1s"}) {
    SCOPED_TRACE(v);
    expectFlagError(renderWith(std::string("--time ") + v), "--time",
                    std::string("must be a positive finite number of seconds, got '") + v + "'");
  }
  // Issue 34: finite but absurd, it rendered forever ("ETA forever").
  expectFlagError(renderWith("--time 1e300"), "--time", "must be at most 2592000 seconds, got '1e300'");
  // And so did a sample count of 2^64 - 1: at most 2^31 - 1, as a YAML budget.
  expectFlagError(renderWith("--spp 18446744073709551615"), "--spp", "must be a whole number in [1, 2147483647]");
  expectFlagError(renderWith("--spp 2147483648"), "--spp", "got '2147483648'");
  expectFlagError(renderWith("--spp 32 --distributed --chunk-spp 2147483648"), "--chunk-spp", "got '2147483648'");
}

// Issue 34, class 6: an output name too long for the file system (with the
// temporary suffix it is first written under) rendered, then failed.
TEST_F(BadFlag, OutputNamesTooLongForTheFileSystemAreRefusedFirst) {
  std::string scene = validScene();
  // ".<name>.config.yaml.tmp-PID" is the longest: 240 + 22 bytes.
  RunResult r = run("render " + scene + " -q --spp 1 -o " + (dir_ / "out" / (std::string(236, 'n') + ".exr")).string());
  expectFlagError(r, "--output", "is too long");
  RunResult ok = run("render " + scene + " -q --spp 1 -o " + (dir_ / "out" / (std::string(200, 'n') + ".exr")).string());
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

// Without roulette a path runs to max_depth: 2^31 - 1 in a closed box ran
// for ever; unlimited (-1) was already refused without rr.
TEST_F(BadFlag, MaxDepthWithoutRouletteHasAMaximum) {
  RunResult r = renderWith("--spp 1 --set max_depth=4097 --set rr=false");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("without rr a path runs to max_depth: at most 4096"), std::string::npos) << r.err;
  EXPECT_TRUE(noOutput());
  EXPECT_EQ(renderWith("--spp 1 --set max_depth=4096 --set rr=false").exitCode, 0);
}

// mode: mmlt keeps a chain per path length: a max_depth of 2^31 - 1
// allocated gigabytes and bootstrapped for ever.
TEST_F(BadFlag, MultiplexedMltHasAMaximumDepth) {
  RunResult r = renderWith("--spp 1 --integrator mlt --set mode=mmlt --set max_depth=4097");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("max_depth must be at most 4096"), std::string::npos) << r.err;
  EXPECT_TRUE(noOutput());
}

TEST_F(BadFlag, AdaptiveNeedsAPixelByPixelIntegratorAndSaneSettings) {
  expectFlagError(renderWith("--spp 4 --integrator bdpt --adaptive"), "--adaptive",
                  "bdpt: it does not estimate each pixel from its own camera samples");
  expectFlagError(renderWith("--spp 4 --adaptive --adaptive-passes 2"), "--adaptive-passes", "got '2'");
  RunResult lonely = renderWith("--spp 4 --adaptive-target 0.1");  // without --adaptive
  EXPECT_EQ(lonely.exitCode, 2) << lonely.err;
  RunResult ok = renderWith("--spp 8 --adaptive --adaptive-target 0.1");
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

TEST_F(BadFlag, SeedMustFitSixtyFourBits) {
  for (const char* v : {"-1", "18446744073709551616", "1e3", "0x1"}) {
    SCOPED_TRACE(v);
    expectFlagError(renderWith(std::string("--spp 1 --seed ") + v), "--seed", std::string("got '") + v + "'");
  }
  // The largest seed is valid.
  RunResult ok = renderWith("--spp 1 --seed 18446744073709551615");
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

TEST_F(BadFlag, PixelIsParsedStrictlyAndMustBeInsideTheFilm) {
  // 4294967299 = 2^32 + 3 used to wrap to 3; "4junk" was read as 4.
  for (const char* v : {"4294967299,4", "3,4junk", "3", "-1,2", "3,,4", " 3,4"}) {
    SCOPED_TRACE(v);
    expectFlagError(renderWith(std::string("--pixel '") + v + "' --sample 0"), "--pixel", "got '");
  }
  expectFlagError(renderWith("--pixel 8,0 --sample 0"), "--pixel", "inside the 8x8 film, got '8,0'");
  expectFlagError(renderWith("--pixel 3,4"), "--sample", "--pixel needs --sample");
  expectFlagError(renderWith("--sample 0"), "--pixel", "--sample needs --pixel");
  expectFlagError(renderWith("--pixel 3,4 --sample -2"), "--sample", "got '-2'");
  RunResult ok = renderWith("--pixel 7,7 --sample 0");
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

TEST_F(BadFlag, WorldScaleMustBePositiveAndFinite) {
  for (const char* v : {"nan", "inf", "0", "-2", "2x"}) {
    SCOPED_TRACE(v);
    expectFlagError(renderWith(std::string("--spp 1 --world-scale ") + v), "--world-scale",
                    std::string("must be a positive finite number, got '") + v + "'");
  }
}

TEST_F(BadFlag, ThreadsAndJobsAreCheckedAsWholeNumbers) {
  expectFlagError(renderWith("--spp 1 --threads -1"), "--threads", "got '-1'");
  expectFlagError(renderWith("--spp 1 --threads 4294967297"), "--threads", "got '4294967297'");
  expectFlagError(run("run " + validScene() + " --jobs 0"), "--jobs", "got '0'");
}

TEST_F(BadFlag, SetNeedsAKeyAndAValue) {
  // An empty value loaded as null: the default, silently.
  expectFlagError(renderWith("--spp 1 --set max_depth="), "--set max_depth", "empty value");
  expectFlagError(renderWith("--spp 1 --set max_depth"), "--set", "expected key=value");
  expectFlagError(renderWith("--spp 1 --set =3"), "--set", "expected key=value");
}

// CLI11's own errors (unknown flag, missing value, exclusive flags) used to
// print a second line; they name the flag.
TEST_F(BadFlag, ParseErrorsAreOneLineNamingTheFlag) {
  expectFlagError(renderWith("--spp 1 --bogus"), "--bogus", "unknown flag '--bogus'");
  expectFlagError(renderWith("--spp 1 --time 1"), "--time", "excludes");
  expectFlagError(renderWith("--spp"), "--spp", "");
  expectFlagError(run("render"), "scene", "required");
}

// -o out.png used to write the EXR to out.png and then the PNG over it.
// (-o NAME.png writes the preview only: tests/python/test_cli.py.)
TEST_F(BadFlag, OutputMustBeAnExrFile) {
  for (const char* name : {"image", "image.txt", "image.png.jpg"}) {
    SCOPED_TRACE(name);
    std::string args = "render " + validScene() + " -q --spp 1 -o " + (dir_ / "out" / name).string();
    expectFlagError(run(args), "--output", "must name an .exr file");
  }
}

// The PNG beside the EXR is a directory: found before rendering, no EXR left.
TEST_F(BadFlag, OutputBesideTheExrThatIsADirectoryIsFoundFirst) {
  for (const char* taken : {"o.png", "o.config.yaml", "o.exr"}) {
    SCOPED_TRACE(taken);
    fs::remove_all(dir_ / "out");
    fs::create_directories(dir_ / "out" / taken);
    RunResult r = run("render " + validScene() + " -q --spp 1 -o " + (dir_ / "out" / "o.exr").string());
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--output"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(std::string(taken) + ": it is a directory"), std::string::npos) << r.err;
    size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir_ / "out")) files += e.is_regular_file();
    EXPECT_EQ(files, 0u) << "a file was left behind";
  }
}

// The output folder is checked before the scene is even read: the scene here
// is broken too, and the error is about --output.
TEST_F(BadFlag, OutputFolderIsCheckedBeforeRendering) {
  std::string broken = write("broken.yaml", scene("  - {type: sphere, radius: 1, materail: white}"));
  std::string file = write("file", "not a folder");
  expectFlagError(run("render " + broken + " -q --spp 1 -o " + file + "/o.exr"), "--output", "not a folder");
  expectFlagError(run("render " + broken + " -q --spp 1 -o " + (dir_ / "out" / "none" / "o.exr").string()),
                  "--output", "folder does not exist");
}

// The scene is broken too: the output folder must be checked first, not
// after a render. /proc refuses new files even to root (who may write to a
// mode-0555 folder, so that case runs only for other users).
TEST_F(BadFlag, UnwritableOutputFolderIsFoundBeforeRendering) {
  std::string broken = write("broken.yaml", scene("  - {type: sphere, radius: 1, materail: white}"));
  RunResult proc = run("render " + broken + " -q --spp 1 -o /proc/lightbench-o.exr");
  EXPECT_EQ(proc.exitCode, 2) << proc.err;
  EXPECT_NE(proc.err.find("'--output': folder is not writable: /proc"), std::string::npos) << proc.err;
  EXPECT_EQ(std::count(proc.err.begin(), proc.err.end(), '\n'), 1) << proc.err;
  if (::geteuid() == 0) return;
  fs::create_directories(dir_ / "out" / "ro");
  ::chmod((dir_ / "out" / "ro").c_str(), 0555);
  RunResult r = run("render " + broken + " -q --spp 1 -o " + (dir_ / "out" / "ro" / "o.exr").string());
  ::chmod((dir_ / "out" / "ro").c_str(), 0755);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("folder is not writable"), std::string::npos) << r.err;
}

}  // namespace
