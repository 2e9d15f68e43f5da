#include "experiments/cli/flag_checks.h"
#include <sstream>
#include <fcntl.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include "core/sampler.h"
#include "experiments/experiment.h"

namespace lb {

namespace {

// The whole of `text` as a base-10 integer of type T (from_chars: no sign for
// unsigned types, no leading '+' or space, out of range is an error).
template <typename T>
bool parseWhole(const std::string& text, T& value) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end && !text.empty();
}

std::string got(const std::string& text) { return ", got '" + text + "'"; }

}  // namespace

CLI::Validator unsignedInteger(uint64_t minimum, const std::string& what, uint64_t maximum) {
  std::string rule = "a whole number in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
  return CLI::Validator(
      [=](std::string& text) {
        uint64_t v = 0;
        if (!parseWhole(text, v) || v < minimum || v > maximum) return "must be " + rule + " (" + what + ")" + got(text);
        return std::string();
      },
      ">= " + std::to_string(minimum));
}

CLI::Validator intInRange(long long minimum, long long maximum, const std::string& what) {
  return CLI::Validator(
      [=](std::string& text) {
        long long v = 0;
        if (!parseWhole(text, v) || v < minimum || v > maximum)
          return "must be a whole number in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "] (" +
                 what + ")" + got(text);
        return std::string();
      },
      ">= " + std::to_string(minimum));
}

CLI::Validator positiveFinite(const std::string& what, double maximum) {
  return CLI::Validator(
      [=](std::string& text) {
        // strtod reads "nan" and "inf" as numbers: both are refused below.
        char* end = nullptr;
        double v = text.empty() ? 0 : std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || !(v > 0))
          return "must be a positive finite number" + (what.empty() ? std::string() : " of " + what) + got(text);
        if (v > maximum) {
          char most[32];
          std::snprintf(most, sizeof most, "%.10g", maximum);
          return "must be at most " + std::string(most) + (what.empty() ? std::string() : " " + what) + got(text);
        }
        return std::string();
      },
      "> 0");
}

CLI::Validator numberInRange(double minimum, double maximum, const std::string& what) {
  return CLI::Validator(
      [=](std::string& text) {
        char* end = nullptr;
        double v = text.empty() ? 0 : std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !(v >= minimum && v <= maximum)) {
          char rule[96];
          std::snprintf(rule, sizeof rule, "must be a number in [%g, %g]", minimum, maximum);
          return rule + (what.empty() ? std::string() : " (" + what + ")") + got(text);
        }
        return std::string();
      },
      "number");
}

CLI::Validator renderFlagCheck(const std::string& flag) {
  if (flag == "--spp") return unsignedInteger(1, "samples per pixel", kMaxSpp);
  if (flag == "--chunk-spp") return unsignedInteger(1, "passes per chunk", kMaxSpp);
  if (flag == "--time") return positiveFinite("seconds", kMaxBudgetSeconds);
  if (flag == "--seed") return unsignedInteger(0, "random seed");
  if (flag == "--threads") return intInRange(0, std::numeric_limits<int>::max(), "worker threads, 0: all cores");
  if (flag == "--resolution") return resolution();
  if (flag == "--crop") return cropWindow();
  if (flag == "--exposure") return numberInRange(-64, 64, "stops");
  if (flag == "--adaptive-passes") return intInRange(4, std::numeric_limits<int>::max(), "uniform passes, at least 4");
  if (flag == "--adaptive-target") return numberInRange(0, std::numeric_limits<double>::max(), "relative error, 0: none");
  throw std::logic_error("renderFlagCheck: no check for " + flag);
}

void checkFileNameFits(const std::string& flag, const std::string& path) {
  namespace fs = std::filesystem;
  // Linux's pids have at most 7 digits (pid_max 4194304).
  const size_t nameBytes = fs::path(path).filename().string().size() + sizeof("..tmp-4194304") - 1;
  const size_t pathBytes = fs::absolute(path).string().size() + sizeof("..tmp-4194304") - 1;
  if (nameBytes > 255)
    throw flagError(flag, "the file name " + fs::path(path).filename().string().substr(0, 24) + "… is too long: written as " +
                              std::to_string(nameBytes) + " bytes (with its temporary suffix), over the file system's 255");
  if (pathBytes > 4095)
    throw flagError(flag, "the path " + path.substr(0, 24) + "… is too long: " + std::to_string(pathBytes) +
                              " bytes with its temporary suffix, over the file system's 4095");
}

bool parsePixel(const std::string& text, int& x, int& y) {
  auto comma = text.find(',');
  if (comma == std::string::npos) return false;
  return parseWhole(text.substr(0, comma), x) && parseWhole(text.substr(comma + 1), y) && x >= 0 && y >= 0;
}

CLI::Validator pixelCoordinates() {
  return CLI::Validator(
      [](std::string& text) {
        int x = 0, y = 0;
        if (!parsePixel(text, x, y)) return "must be X,Y: two whole non-negative numbers" + got(text);
        return std::string();
      },
      "X,Y");
}

CLI::Validator outputFileName() {
  return CLI::Validator(
      [](std::string& text) {
        std::filesystem::path p(text);
        if ((p.extension() != ".exr" && p.extension() != ".png") || p.stem().empty())
          return "must name an .exr file (the .png preview and .config.yaml are written beside it) or a .png "
                 "(the preview only)" + got(text);
        return std::string();
      },
      "FILE.exr|FILE.png");
}

bool parseResolution(const std::string& text, int& width, int& height) {
  auto x = text.find('x');
  if (x == std::string::npos) return false;
  auto whole = [](const std::string& s, int& v) {
    if (s.empty() || s.size() > 5 || s.find_first_not_of("0123456789") != std::string::npos) return false;
    v = std::stoi(s);
    return v >= 1 && v <= 8192;  // the largest image readExr (and so the report, load_run) reads
  };
  return whole(text.substr(0, x), width) && whole(text.substr(x + 1), height);
}

bool parseCrop(const std::string& text, int (&w)[4]) {
  std::stringstream in(text);
  std::string part;
  for (int i = 0; i < 4; ++i) {
    if (!std::getline(in, part, ',') || part.empty() || part.size() > 5 ||
        part.find_first_not_of("0123456789") != std::string::npos)
      return false;
    w[i] = std::stoi(part);
  }
  return !std::getline(in, part) && w[0] < w[2] && w[1] < w[3];
}

CLI::Validator cropWindow() {
  return CLI::Validator(
      [](std::string& text) {
        int w[4];
        return parseCrop(text, w) ? std::string() : "must be X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1" + got(text);
      },
      "X0,Y0,X1,Y1");
}

CLI::Validator resolution() {
  return CLI::Validator(
      [](std::string& text) {
        int w = 0, h = 0;
        return parseResolution(text, w, h) ? std::string()
                                           : "must be WIDTHxHEIGHT, each from 1 to 8192 (e.g. 640x480)" + got(text);
      },
      "WxH");
}

ConfigError flagError(const std::string& flag, const std::string& message) {
  return ConfigError("command line", 0, flag, message);
}

void checkWritableFolder(const std::string& flag, const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path existing = dir.empty() ? fs::path(".") : dir;
  while (!fs::exists(existing, ec) && existing.has_parent_path() && existing.parent_path() != existing)
    existing = existing.parent_path();
  if (!fs::exists(existing, ec)) existing = ".";
  if (!fs::is_directory(existing, ec)) throw flagError(flag, "not a folder: " + existing.string());
  fs::path probe = existing / (".lightbench-write-test-" + std::to_string(::getpid()));
  int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0 && errno != EEXIST)
    throw flagError(flag, "folder is not writable: " + existing.string() + " (" + std::strerror(errno) + ")");
  if (fd >= 0) ::close(fd), ::unlink(probe.c_str());
}

}  // namespace lb
