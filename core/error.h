#pragma once
// Configuration errors carry where they come from: file, line and key. They are
// thrown anywhere in core/ and caught once at the command-line entry point,
// which prints the message and exits with code 2. Nothing in core/ exits.
#include <stdexcept>
#include <string>

namespace lb {

class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, int line, const std::string& key, const std::string& message)
      : std::runtime_error(format(file, line, 0, key, message)), file_(file), line_(line), key_(key) {}
  // For token-level errors (the pbrt tokenizer): "file:line:column: message".
  ConfigError(const std::string& file, int line, int column, const std::string& key, const std::string& message)
      : std::runtime_error(format(file, line, column, key, message)), file_(file), line_(line), key_(key) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  static std::string format(const std::string& file, int line, int column, const std::string& key, const std::string& msg) {
    std::string where = file.empty() ? std::string("<input>") : file;
    if (line > 0) where += ":" + std::to_string(line);
    if (line > 0 && column > 0) where += ":" + std::to_string(column);
    return where + ": " + (key.empty() ? "" : "'" + key + "': ") + msg;
  }
  std::string file_;
  int line_;
  std::string key_;
};

// Non-fatal notes for the user (degenerate triangles skipped, and so on).
void warn(const std::string& message);

}  // namespace lb
