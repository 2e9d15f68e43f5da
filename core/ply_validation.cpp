// The PLY check (see mesh_validation.h for why these checks exist).
//
// OpenMesh 9.0's PLY reader (PLYReader.cc) reads the header token by token
// without checking that a token parsed, so a bad count loops forever; it uses
// the counts to reserve memory before reading data; it indexes with face
// indices unchecked; and in binary files it finds the data by a fixed offset
// from the token before "end_header". Here the header must follow the PLY
// grammar line by line (which the token reader then reads the same way), the
// counts must fit in the file, and the vertex and face data are scanned once:
// ascii token by token, binary by fixed sizes, face indices range-checked.
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>
#include "core/mesh_validation.h"

namespace lb {

namespace {
using meshcheck::failAt;
using meshcheck::shown;

struct PlyType {
  const char* name;
  int size;
  bool isFloat, isSigned;
};
// The scalar types of the PLY specification, old and new names.
const PlyType kTypes[] = {{"char", 1, false, true},    {"uchar", 1, false, false},  {"short", 2, false, true},
                          {"ushort", 2, false, false}, {"int", 4, false, true},     {"uint", 4, false, false},
                          {"float", 4, true, true},    {"double", 8, true, true},   {"int8", 1, false, true},
                          {"uint8", 1, false, false},  {"int16", 2, false, true},   {"uint16", 2, false, false},
                          {"int32", 4, false, true},   {"uint32", 4, false, false}, {"float32", 4, true, true},
                          {"float64", 8, true, true}};

const PlyType* findType(const std::string& name) {
  for (const auto& t : kTypes)
    if (name == t.name) return &t;
  return nullptr;
}

// How OpenMesh reads a property's values, hence what they must look like.
enum class Use { Other, Coordinate, Color, Indices };

struct Property {
  std::string name;
  const PlyType* type = nullptr;
  const PlyType* countType = nullptr;  // lists only
  Use use = Use::Other;
};

struct Element {
  std::string name;
  uint64_t count = 0, line = 0;
  std::vector<Property> props;
};

struct Header {
  bool binary = false, bigEndian = false;
  uint64_t dataStart = 0, dataLine = 0;
  std::vector<Element> elements;
};

// Buffered bytes of the file with their offset and line number.
class Bytes {
 public:
  Bytes(const std::string& path, uint64_t start) : in_(path, std::ios::binary), offset_(start) {
    in_.seekg(std::streamoff(start));
  }
  int get() {
    if (pos_ == end_) {
      in_.read(buf_, sizeof buf_);
      pos_ = 0;
      end_ = size_t(in_.gcount());
      if (end_ == 0) return -1;
    }
    ++offset_;
    unsigned char c = static_cast<unsigned char>(buf_[pos_++]);
    if (c == '\n') ++line_;
    return c;
  }
  uint64_t offset() const { return offset_; }
  uint64_t line() const { return line_; }
  void setLine(uint64_t line) { line_ = line; }

 private:
  std::ifstream in_;
  char buf_[1 << 16];
  size_t pos_ = 0, end_ = 0;
  uint64_t offset_ = 0, line_ = 1;
};

std::vector<std::string> tokensOf(const std::string& line) {
  std::vector<std::string> tokens;
  std::string token;
  for (char c : line + ' ') {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!token.empty()) tokens.push_back(token);
      token.clear();
    } else {
      token += c;
    }
  }
  return tokens;
}

bool isOneOf(const std::string& s, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (s == n) return true;
  return false;
}

Property parseProperty(const std::string& path, uint64_t line, const std::vector<std::string>& t, const Element& e) {
  Property p;
  bool list = t.size() >= 2 && t[1] == "list";
  if (t.size() != (list ? 5u : 3u))
    failAt(path, line, list ? "expected 'property list COUNTTYPE TYPE NAME'" : "expected 'property TYPE NAME'");
  p.name = t.back();
  p.type = findType(t[list ? 3 : 1]);
  if (!p.type) failAt(path, line, "unknown property type " + shown(t[list ? 3 : 1]));
  // OpenMesh guesses which of the two words is the type: a name that is a type
  // name would swap them.
  if (findType(p.name)) failAt(path, line, "property name " + shown(p.name) + " is a type name");
  for (const auto& q : e.props)
    if (q.name == p.name) failAt(path, line, "duplicate property " + shown(p.name));
  if (list) {
    p.countType = findType(t[2]);
    if (!p.countType) failAt(path, line, "unknown list count type " + shown(t[2]));
    if (e.name != "face" || !isOneOf(p.name, {"vertex_indices", "vertex_index"}))
      failAt(path, line, "list property " + shown(p.name) + " in element " + shown(e.name) +
                             " is not supported (only face vertex_indices)");
    if (!isOneOf(t[2], {"uchar", "uint8", "uint16", "int"}))
      failAt(path, line, "list count type " + shown(t[2]) + " is not supported (use uchar, uint8, uint16 or int)");
    if (p.type->isFloat) failAt(path, line, "vertex indices of type " + shown(t[3]) + " (need an integer type)");
    p.use = Use::Indices;
    return p;
  }
  bool colorName = isOneOf(p.name, {"red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue"});
  if (e.name == "vertex" && isOneOf(p.name, {"x", "y", "z", "nx", "ny", "nz", "u", "v", "s", "t"}))
    p.use = Use::Coordinate;
  else if ((e.name == "vertex" || e.name == "face") && colorName)
    p.use = Use::Color;
  // OpenMesh reads float colours only as 4-byte floats, coordinates only as floats.
  if (p.use == Use::Color && p.type->isFloat && p.type->size == 8)
    failAt(path, line, "colour property " + shown(p.name) + " of type double is not supported");
  return p;
}

// Which offset OpenMesh's binary reader takes as the start of the data: 12 (or
// 14 for "\r\n") bytes after the stream position before it read "end_header".
uint64_t openMeshDataStart(const std::string& header, uint64_t posBeforeEnd) {
  bool crlf = header.compare(posBeforeEnd, 2, "\r\n") == 0;
  return posBeforeEnd + (crlf ? 14 : 12);
}

void checkElements(const std::string& path, const Header& h) {
  const Element *vertex = nullptr, *face = nullptr;
  for (const auto& e : h.elements) {
    if (e.name == "vertex" || e.name == "face") {
      if ((e.name == "vertex" ? vertex : face) != nullptr) failAt(path, e.line, "second " + e.name + " element");
      (e.name == "vertex" ? vertex : face) = &e;
    }
    if (e.name == "face" && !vertex) failAt(path, e.line, "face element before the vertex element");
    if (e.props.empty() && e.count) failAt(path, e.line, "element " + shown(e.name) + " has no properties");
  }
  if (!vertex) failAt(path, 0, "PLY header has no vertex element");
  if (!face || face->count == 0) failAt(path, face ? face->line : 0, "no faces");
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const auto& p : vertex->props) found |= p.name == axis;
    if (!found) failAt(path, vertex->line, std::string("vertex element has no '") + axis + "' property");
  }
  bool indices = false;
  for (const auto& p : face->props) indices |= p.use == Use::Indices;
  if (!indices) failAt(path, face->line, "face element has no vertex_indices list");
  for (const auto& e : h.elements)
    for (const auto& p : e.props)
      if (h.binary && p.use == Use::Coordinate && !p.type->isFloat)
        failAt(path, e.line, "binary property " + shown(p.name) + " must be float or double");
}

// Far above any real header; stops a binary file without newlines being read whole.
constexpr size_t kMaxHeader = size_t(1) << 20;

Header parseHeader(const std::string& path) {
  Bytes in(path, 0);
  Header h;
  std::string header;  // raw bytes read so far
  uint64_t omPos = 0;  // OpenMesh's stream position after the last keyword it processed
  for (uint64_t line = 1;; ++line) {
    uint64_t lineStart = header.size();
    std::string text;
    int c;
    while ((c = in.get()) >= 0 && c != '\n' && header.size() + text.size() <= kMaxHeader) text += char(c);
    header += text;
    if (header.size() > kMaxHeader) failAt(path, 0, "PLY header longer than 1 MB (no end_header?)");
    if (c < 0) failAt(path, 0, "PLY header has no end_header");
    header += '\n';
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::vector<std::string> t = tokensOf(text);
    size_t lastTokenEnd = lineStart + text.find_last_not_of(" \t\v\f\r") + 1;
    if (line == 1) {
      if (t.size() != 1 || t[0] != "ply") failAt(path, 0, "not a PLY file (first line is not 'ply')");
      continue;
    }
    if (line == 2) {
      if (t.size() != 3 || t[0] != "format" || !isOneOf(t[1], {"ascii", "binary_little_endian", "binary_big_endian"}) ||
          t[2] != "1.0")
        failAt(path, line, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      h.binary = t[1] != "ascii";
      h.bigEndian = t[1] == "binary_big_endian";
      omPos = lastTokenEnd;
      continue;
    }
    if (t.empty()) continue;
    if (t[0] == "end_header") {
      if (t.size() != 1) failAt(path, line, "unexpected text after end_header");
      h.dataStart = header.size();
      h.dataLine = line + 1;
      if (h.binary && openMeshDataStart(header, omPos) != h.dataStart)
        failAt(path, line, "binary PLY header layout the mesh reader misreads (put end_header right after an "
                           "element or property line, without trailing spaces)");
      checkElements(path, h);
      return h;
    }
    if (t[0] == "comment") {
      omPos = header.size();  // OpenMesh skips the rest of the line, newline included
    } else if (t[0] == "obj_info") {
      // OpenMesh reads obj_info's words as keywords: none may be one.
      for (const auto& w : t)
        if (isOneOf(w, {"comment", "element", "property", "end_header"}))
          failAt(path, line, "obj_info line contains the keyword " + shown(w));
      omPos = lastTokenEnd;
    } else if (t[0] == "element") {
      int64_t count;
      if (t.size() != 3) failAt(path, line, "expected 'element NAME COUNT'");
      if (!meshcheck::parseInteger(t[2], count) || t[2][0] == '-' || t[2][0] == '+')
        failAt(path, line, "element count " + shown(t[2]) + " is not a non-negative integer");
      h.elements.push_back({t[1], uint64_t(count), line, {}});
      omPos = lastTokenEnd;
    } else if (t[0] == "property") {
      if (h.elements.empty()) failAt(path, line, "property before any element");
      h.elements.back().props.push_back(parseProperty(path, line, t, h.elements.back()));
      omPos = lastTokenEnd;
    } else {
      failAt(path, line, "unknown PLY header keyword " + shown(t[0]));
    }
  }
}

// The least number of data bytes an element needs: refuse impossible counts
// before anything (ours or OpenMesh's) allocates or loops over them.
void checkSizes(const std::string& path, const Header& h, uint64_t fileSize) {
  uint64_t needed = 0, available = fileSize - h.dataStart;
  for (const auto& e : h.elements) {
    uint64_t perItem = 0;
    for (const auto& p : e.props) {
      if (h.binary) perItem += p.countType ? p.countType->size + 3 * p.type->size : p.type->size;
      else perItem += p.countType ? 4 : 1;  // at least one byte per token, lists at least 4 tokens
    }
    // Division, not multiplication: a count near 2^60 must not overflow.
    if (perItem && e.count > (available - needed) / perItem)
      failAt(path, e.line, "element " + shown(e.name) + " count " + std::to_string(e.count) + " needs more data than the " +
                               std::to_string(available) + " bytes after the header");
    needed += e.count * perItem;
    // OpenMesh's vertex and face handles are ints.
    if (e.count > uint64_t(std::numeric_limits<int32_t>::max()))
      failAt(path, e.line, "element count " + std::to_string(e.count) + " is too large");
    if (e.name == "face") return;  // OpenMesh stops reading after the faces
  }
}

// One pass over the data OpenMesh will read (up to the face element).
class DataScan {
 public:
  DataScan(const std::string& path, const Header& h) : path_(path), h_(h), in_(path, h.dataStart) {
    in_.setLine(h.dataLine);
  }
  void run() {
    for (const auto& e : h_.elements) {
      for (uint64_t i = 0; i < e.count; ++i)
        for (const auto& p : e.props) h_.binary ? binaryValue(e, p, i) : asciiValue(e, p, i);
      if (e.name == "vertex") vertices_ = e.count;
      if (e.name == "face") return;
    }
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    if (h_.binary) failAt(path_, 0, "byte " + std::to_string(at_) + ": " + message);
    failAt(path_, line_, message);
  }
  void ended(const Element& e, uint64_t i) {
    at_ = in_.offset();
    line_ = in_.line();
    fail("file ends inside element " + shown(e.name) + " (item " + std::to_string(i) + " of " +
         std::to_string(e.count) + ")");
  }
  void checkArity(int64_t n) {
    if (n < 3) fail("face has " + std::to_string(n) + " vertices (at least 3 needed)");
    if (n > std::numeric_limits<int32_t>::max()) fail("face has " + std::to_string(n) + " vertices");
  }
  void checkIndex(int64_t index) {
    if (index < 0 || uint64_t(index) >= vertices_)
      fail("face index " + std::to_string(index) + " out of range (" + std::to_string(vertices_) + " vertices)");
  }

  bool token(std::string& out) {
    int c;
    while ((c = in_.get()) >= 0 && std::isspace(c)) {
    }
    if (c < 0) return false;
    line_ = in_.line();
    out.assign(1, char(c));
    while ((c = in_.get()) >= 0 && !std::isspace(c)) out += char(c);
    return true;
  }
  int64_t asciiInteger(const Element& e, uint64_t i, const char* what) {
    std::string t;
    int64_t v;
    if (!token(t)) ended(e, i);
    if (!meshcheck::parseInteger(t, v)) fail(std::string(what) + " " + shown(t) + " is not an integer");
    return v;
  }
  void asciiValue(const Element& e, const Property& p, uint64_t i) {
    std::string t;
    if (p.use == Use::Indices) {
      int64_t n = asciiInteger(e, i, "face vertex count");
      checkArity(n);
      for (int64_t k = 0; k < n; ++k) checkIndex(asciiInteger(e, i, "face index"));
      return;
    }
    if (!token(t)) ended(e, i);
    double f;
    int64_t v;
    if ((p.use == Use::Coordinate || (p.use == Use::Color && p.type->isFloat)) && !meshcheck::parseFloat(t, f))
      fail("property " + shown(p.name) + " value " + shown(t) + " is not a finite number");
    if (p.use == Use::Color && !p.type->isFloat &&
        (!meshcheck::parseInteger(t, v) || v < std::numeric_limits<int32_t>::min() ||
         v > std::numeric_limits<int32_t>::max()))
      fail("property " + shown(p.name) + " value " + shown(t) + " is not an integer");
  }

  // Reads one binary scalar: integers into i, floats into f.
  void binaryScalar(const Element& e, uint64_t item, const PlyType& t, int64_t& i, double& f) {
    at_ = in_.offset();
    unsigned char b[8];
    for (int k = 0; k < t.size; ++k) {
      int c = in_.get();
      if (c < 0) ended(e, item);
      b[k] = static_cast<unsigned char>(c);
    }
    uint64_t u = 0;
    for (int k = 0; k < t.size; ++k) u |= uint64_t(b[h_.bigEndian ? t.size - 1 - k : k]) << (8 * k);
    if (t.isFloat && t.size == 4) {
      uint32_t u32 = uint32_t(u);
      float x;
      std::memcpy(&x, &u32, 4);
      f = x;
    } else if (t.isFloat) {
      std::memcpy(&f, &u, 8);
    } else if (t.isSigned) {
      int shift = 64 - 8 * t.size;
      i = int64_t(u << shift) >> shift;
    } else {
      i = int64_t(u);
    }
  }
  void binaryValue(const Element& e, const Property& p, uint64_t item) {
    int64_t i = 0;
    double f = 0;
    if (p.use == Use::Indices) {
      binaryScalar(e, item, *p.countType, i, f);
      checkArity(i);
      for (int64_t k = 0, n = i; k < n; ++k) {
        binaryScalar(e, item, *p.type, i, f);
        checkIndex(i);
      }
      return;
    }
    binaryScalar(e, item, *p.type, i, f);
    // OpenMesh stores coordinates as float: a double beyond float range becomes inf.
    if (p.use == Use::Coordinate && !(std::abs(f) <= std::numeric_limits<float>::max()))
      fail("property " + shown(p.name) + " is not a finite number");
  }

  const std::string& path_;
  const Header& h_;
  Bytes in_;
  uint64_t vertices_ = 0, at_ = 0, line_ = 0;
};

}  // namespace

void validatePlyFile(const std::string& path) {
  Header h = parseHeader(path);
  checkSizes(path, h, std::filesystem::file_size(path));
  DataScan(path, h).run();
}

}  // namespace lb
