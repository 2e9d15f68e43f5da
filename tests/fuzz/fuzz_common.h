#pragma once
// Helpers shared by the libFuzzer targets: a private temporary folder per
// process (the loaders under test take file paths) and the rule for what
// counts as a clean rejection.
#include <stdlib.h>
#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include "core/error.h"

namespace lbfuzz {

// One folder per process (parallel -jobs must not share files), removed at
// exit so a fuzzing session leaves nothing behind in TMPDIR.
inline const std::filesystem::path& tempDir() {
  static const std::filesystem::path dir = [] {
    std::string base = (std::filesystem::temp_directory_path() / "lightbench-fuzz-XXXXXX").string();
    if (!mkdtemp(base.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    static std::filesystem::path forCleanup;
    forCleanup = base;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(forCleanup, ec);
    });
    return std::filesystem::path(base);
  }();
  return dir;
}

inline void writeFile(const std::filesystem::path& path, const uint8_t* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  if (!out) std::abort();  // a full disk would otherwise look like a loader finding
}

inline bool envFlag(const char* name) {
  const char* s = std::getenv(name);
  return s && std::strcmp(s, "1") == 0;
}

// ConfigError is the documented outcome of bad input; other std::exceptions
// (std::runtime_error from the mesh reader, YAML::Exception...) are accepted
// too. With LIGHTBENCH_FUZZ_STRICT=1 the scene and experiment targets treat a
// non-ConfigError exception as a finding: issue 12 wants file:line:key errors.
// LIGHTBENCH_FUZZ_VERBOSE=1 prints each rejection (to see why a seed fails).
inline void rejected(const std::exception& e, bool configErrorExpected) {
  static const bool strict = envFlag("LIGHTBENCH_FUZZ_STRICT"), verbose = envFlag("LIGHTBENCH_FUZZ_VERBOSE");
  if (verbose) std::fprintf(stderr, "fuzz: rejected: %s\n", e.what());
  if (strict && configErrorExpected && !dynamic_cast<const lb::ConfigError*>(&e)) {
    std::fprintf(stderr, "fuzz: not a ConfigError: %s\n", e.what());
    std::abort();
  }
}

}  // namespace lbfuzz
