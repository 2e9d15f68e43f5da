#pragma once
// CLI11 validators for `lightbench` flags. They run on the text as typed,
// before CLI11 converts it: CLI11's own conversion goes through strtoull,
// which turns "-1" and "2^64" into 2^64-1 and accepts "0x10" or "010". A
// failed check becomes one line "--flag: must be ..., got '...'".
#include <CLI/CLI.hpp>
#include <filesystem>
#include <limits>
#include <string>
#include "core/error.h"

namespace lb {

// A whole decimal number in [minimum, maximum]: no sign, no junk, no overflow.
CLI::Validator unsignedInteger(uint64_t minimum, const std::string& what,
                               uint64_t maximum = std::numeric_limits<uint64_t>::max());
// A whole decimal number in [minimum, maximum] (for int-typed flags).
CLI::Validator intInRange(long long minimum, long long maximum, const std::string& what);
// A number > 0 that is not NaN or infinite, at most `maximum`; `what` names
// its unit (a time budget's maximum is 30 days: `--time 1e300` ran forever).
CLI::Validator positiveFinite(const std::string& what, double maximum = std::numeric_limits<double>::max());
// A number in [minimum, maximum]; NaN refused (CLI::Range and
// CLI::NonNegativeNumber let it through: `--exposure nan` wrote a black PNG).
CLI::Validator numberInRange(double minimum, double maximum, const std::string& what);
// The check of one of `lightbench render`'s valued flags: --spp, --chunk-spp, --time,
// --seed, --threads, --resolution, --crop, --exposure, --adaptive-passes,
// --adaptive-target. The command line and the Python package's render()
// (its arguments as the flags' text) go through these same checks.
CLI::Validator renderFlagCheck(const std::string& flag);
// "X,Y": two whole non-negative decimal numbers that fit an int.
CLI::Validator pixelCoordinates();
// The render's output: NAME.exr (the float image; the PNG preview and the
// configuration are written beside it under the same stem) or NAME.png (the
// preview only, said so; never an EXR under a .png name). Other extensions are
// refused: they would be overwritten by, or mistaken for, one of these.
CLI::Validator outputFileName();
// "WxH": two whole numbers from 1 to 8192 (what readExr reads), e.g. 640x480.
CLI::Validator resolution();
bool parseResolution(const std::string& text, int& width, int& height);
// "X0,Y0,X1,Y1": four whole numbers with X0 < X1 and Y0 < Y1 (the film's
// bounds are checked once the scene is loaded).
CLI::Validator cropWindow();
bool parseCrop(const std::string& text, int (&window)[4]);

// A ConfigError about a flag: "command line: 'flag': message".
ConfigError flagError(const std::string& flag, const std::string& message);
// Throws flagError(flag, ...) unless a file can be created in `dir`, or, when
// `dir` does not exist yet, in its nearest existing ancestor (where it would
// be created). The test creates and removes a file: access(W_OK) says yes to
// root on a read-only folder and on /proc, and the failure would otherwise
// come after the render.
void checkWritableFolder(const std::string& flag, const std::filesystem::path& dir);

// Throws flagError(flag, ...) unless `path` and the temporary name it is
// first written under (.NAME.tmp-PID, core/image.cpp) fit the file system's
// limits: 255 bytes a name (NAME_MAX), 4095 a path (PATH_MAX). A name of 250
// bytes rendered, then failed to write (issue 34, class 6).
void checkFileNameFits(const std::string& flag, const std::string& path);

// Strict "X,Y" parsing shared by the validator and the render command.
bool parsePixel(const std::string& text, int& x, int& y);

}  // namespace lb
