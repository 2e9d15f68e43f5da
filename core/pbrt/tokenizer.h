#pragma once
// pbrt-v4's scene format, token by token (pbrt-v4 src/pbrt/parser.cpp,
// "Tokenizer"): `#` comments to the end of the line, "quoted strings"
// (with \" \\ \n \t escapes, on one line), `[` and `]`, and bare words
// (directives, numbers, true/false). Each token keeps its file, line and
// column, so that every error names file:line:column.
#include <string>
#include <string_view>

namespace lb::pbrt {

struct Token {
  enum class Kind { Word, String, OpenBracket, CloseBracket, End };
  Kind kind = Kind::End;
  std::string text;  // a string's contents with its escapes resolved
  int line = 0, column = 0;
};

class Tokenizer {
 public:
  Tokenizer(std::string text, std::string file) : text_(std::move(text)), file_(std::move(file)) {}
  Token next();
  // Looks at the next token without consuming it.
  const Token& peek();
  const std::string& file() const { return file_; }
  // A ConfigError at `t`: "file:line:column: message".
  [[noreturn]] void fail(const Token& t, const std::string& message) const;

 private:
  Token scan();
  std::string text_, file_;
  size_t pos_ = 0;
  int line_ = 1, column_ = 1;
  Token peeked_;
  bool hasPeeked_ = false;
};

// A word read as a number (pbrt reads them with strtod): nullopt-like false
// when `text` is not entirely a finite number.
bool parseNumber(std::string_view text, double& out);

}  // namespace lb::pbrt
