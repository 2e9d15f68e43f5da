#include "core/pbrt/tokenizer.h"
#include <cctype>
#include <cmath>
#include <cstdlib>
#include "core/error.h"

namespace lb::pbrt {

void Tokenizer::fail(const Token& t, const std::string& message) const {
  throw ConfigError(file_, t.line, t.column, "", message);
}

const Token& Tokenizer::peek() {
  if (!hasPeeked_) {
    peeked_ = scan();
    hasPeeked_ = true;
  }
  return peeked_;
}

Token Tokenizer::next() {
  if (hasPeeked_) {
    hasPeeked_ = false;
    return std::move(peeked_);
  }
  return scan();
}

Token Tokenizer::scan() {
  auto advance = [&] {
    if (text_[pos_] == '\n') ++line_, column_ = 1;
    else ++column_;
    ++pos_;
  };
  for (;;) {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) advance();
    if (pos_ < text_.size() && text_[pos_] == '#') {
      while (pos_ < text_.size() && text_[pos_] != '\n') advance();
      continue;
    }
    break;
  }
  Token t;
  t.line = line_, t.column = column_;
  if (pos_ >= text_.size()) return t;
  char c = text_[pos_];
  if (c == '[' || c == ']') {
    t.kind = c == '[' ? Token::Kind::OpenBracket : Token::Kind::CloseBracket;
    t.text = std::string(1, c);
    advance();
    return t;
  }
  if (c == '"') {
    t.kind = Token::Kind::String;
    advance();
    for (;;) {
      if (pos_ >= text_.size() || text_[pos_] == '\n') fail(t, "unterminated string (a string ends on its line with \")");
      char d = text_[pos_];
      if (d == '"') {
        advance();
        return t;
      }
      if (d == '\\') {
        Token at{Token::Kind::String, "", line_, column_};
        advance();
        if (pos_ >= text_.size()) fail(t, "unterminated string (a string ends on its line with \")");
        static const std::string from = "bfnrt\"\\'", to = "\b\f\n\r\t\"\\'";
        size_t k = from.find(text_[pos_]);
        if (k == std::string::npos) {
          fail(at, std::string("unknown escape '\\") + text_[pos_] + "' in a string");
        }
        t.text += to[k];
        advance();
        continue;
      }
      if (d == '\0' || (static_cast<unsigned char>(d) < 0x20 && d != '\t')) {
        Token at{Token::Kind::String, "", line_, column_};
        fail(at, "a control character inside a string");
      }
      t.text += d;
      advance();
    }
  }
  t.kind = Token::Kind::Word;
  while (pos_ < text_.size()) {
    char d = text_[pos_];
    if (std::isspace(static_cast<unsigned char>(d)) || d == '"' || d == '[' || d == ']' || d == '#') break;
    if (static_cast<unsigned char>(d) < 0x20 || d == 0x7f) {
      Token at{Token::Kind::Word, "", line_, column_};
      fail(at, "unexpected control character (byte " + std::to_string(static_cast<unsigned char>(d)) + ")");
    }
    t.text += d;
    advance();
  }
  return t;
}

bool parseNumber(std::string_view text, double& out) {
  if (text.empty() || text.size() > 64) return false;
  char c = text[0];
  if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.')) return false;
  for (char d : text)
    if (d == 'x' || d == 'X' || d == 'n' || d == 'N') return false;  // no hex, inf or nan
  std::string s(text);
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

}  // namespace lb::pbrt
