// Shared helpers of the mesh-file checks, and the OBJ check.
//
// The OBJ rules mirror OpenMesh 9.0's OBJ reader (OBJReader.cc), which reads the
// file twice: once for v/vt/vn, once for faces. It trims " \t\r\n" from each
// line, skips empty lines and '#' comments, and splits on whitespace. It then
// indexes its arrays with whatever the face tokens say: index 0, an index past
// the last vertex, or a token like "/1" (no vertex) crash it. So every face
// token must resolve, and every v/vt/vn line must parse (a line that does not
// is counted by one pass but not stored by the other, shifting indices).
#include "core/mesh_validation.h"
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace lb {
namespace meshcheck {

void failAt(const std::string& path, uint64_t line, const std::string& message) {
  std::string where = line ? path + ":" + std::to_string(line) : path;
  throw std::runtime_error(where + ": " + message);
}

std::string shown(const std::string& token) {
  std::string out = "'";
  for (size_t i = 0; i < token.size() && i < 32; ++i) {
    unsigned char c = static_cast<unsigned char>(token[i]);
    out += std::isprint(c) ? char(c) : '?';  // never a newline or control byte in the message
  }
  return out + (token.size() > 32 ? "...'" : "'");
}

bool parseInteger(const std::string& token, int64_t& value) {
  size_t i = (!token.empty() && (token[0] == '-' || token[0] == '+')) ? 1 : 0;
  if (i == token.size() || token.size() - i > 18) return false;  // 18 digits always fit in int64
  for (size_t j = i; j < token.size(); ++j)
    if (!std::isdigit(static_cast<unsigned char>(token[j]))) return false;
  value = std::strtoll(token.c_str(), nullptr, 10);
  return true;
}

bool parseFloat(const std::string& token, double& value) {
  // Only decimal notation: strtof would also take "nan", "inf" and hex floats,
  // which the readers' `stream >> float` refuses or reads differently.
  if (token.empty() || token.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;
  char* end = nullptr;
  float f = std::strtof(token.c_str(), &end);
  if (end != token.c_str() + token.size() || !std::isfinite(f)) return false;
  value = f;
  return true;
}

}  // namespace meshcheck

namespace {
using meshcheck::failAt;
using meshcheck::shown;

std::vector<std::string> splitWhitespace(const std::string& line) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

// The line as OpenMesh sees it: trimmed of " \t\r\n" on both sides.
std::string trimObjLine(const std::string& line) {
  size_t start = line.find_first_not_of(" \t\r\n");
  if (start == std::string::npos) return "";
  return line.substr(start, line.find_last_not_of(" \t\r\n") - start + 1);
}

struct ObjCounts {
  int64_t positions = 0, texcoords = 0, normals = 0, faces = 0;
};

void checkObjNumbers(const std::string& path, uint64_t line, const std::vector<std::string>& tokens, size_t needed,
                     const char* what) {
  if (tokens.size() < needed + 1)
    failAt(path, line, std::string(what) + " needs " + std::to_string(needed) + " numbers, found " +
                           std::to_string(tokens.size() - 1));
  for (size_t i = 1; i <= needed; ++i) {
    double v;
    if (!meshcheck::parseFloat(tokens[i], v))
      failAt(path, line, std::string(what) + " coordinate " + shown(tokens[i]) + " is not a finite number");
  }
}

// One OBJ index (1-based, negative = counted back from the last one so far).
void checkObjIndex(const std::string& path, uint64_t line, const std::string& text, int64_t count, const char* what,
                   const char* plural) {
  int64_t index;
  if (!meshcheck::parseInteger(text, index))
    failAt(path, line, std::string("face ") + what + " index " + shown(text) + " is not an integer");
  if (index == 0) failAt(path, line, std::string("face ") + what + " index 0 (OBJ indices start at 1)");
  if (index > count || -index > count)
    failAt(path, line, std::string("face ") + what + " index " + std::to_string(index) + " out of range (" +
                           std::to_string(count) + " " + plural + ")");
}

void checkObjFace(const std::string& path, uint64_t line, const std::vector<std::string>& tokens, const ObjCounts& n) {
  if (tokens.size() < 4)
    failAt(path, line, "face has " + std::to_string(tokens.size() - 1) + " vertices (at least 3 needed)");
  for (size_t i = 1; i < tokens.size(); ++i) {
    // v, v/vt, v//vn or v/vt/vn; only the vt part may be empty.
    std::vector<std::string> parts;
    size_t start = 0;
    for (size_t slash; (slash = tokens[i].find('/', start)) != std::string::npos; start = slash + 1)
      parts.push_back(tokens[i].substr(start, slash - start));
    parts.push_back(tokens[i].substr(start));
    if (parts.size() > 3 || parts[0].empty() || (parts.size() == 3 && parts[2].empty()))
      failAt(path, line, "face vertex " + shown(tokens[i]) + " is not v, v/vt, v//vn or v/vt/vn");
    checkObjIndex(path, line, parts[0], n.positions, "vertex", "vertices");
    if (parts.size() > 1 && !parts[1].empty())
      checkObjIndex(path, line, parts[1], n.texcoords, "texture coordinate", "vt lines");
    if (parts.size() > 2) checkObjIndex(path, line, parts[2], n.normals, "normal", "vn lines");
  }
}

// OpenMesh opens the material library itself; a FIFO or device there (e.g.
// /dev/zero) would make it read forever.
void checkMaterialLibrary(const std::string& path, uint64_t line, const std::string& trimmed) {
  std::string name = trimObjLine(trimmed.substr(6));
  if (name.empty()) return;
  std::filesystem::path lib = std::filesystem::path(path).parent_path() / name;
  std::error_code ec;
  if (std::filesystem::exists(lib, ec) && !std::filesystem::is_regular_file(lib, ec))
    failAt(path, line, "mtllib " + shown(name) + " is not a regular file");
}
}  // namespace

ObjFaceGroups validateObjFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) failAt(path, 0, "cannot open mesh file");
  ObjCounts n;
  ObjFaceGroups groups;
  int current = -1;
  std::unordered_map<int64_t, int64_t> vertexTexcoord;
  std::string raw;
  for (uint64_t line = 1; std::getline(in, raw); ++line) {
    std::string trimmed = trimObjLine(raw);
    // OpenMesh also skips a line that still starts with whitespace (\v, \f).
    if (trimmed.empty() || trimmed[0] == '#' || std::isspace(static_cast<unsigned char>(trimmed[0]))) continue;
    std::vector<std::string> tokens = splitWhitespace(trimmed);
    const std::string& key = tokens[0];
    if (key == "v") {
      checkObjNumbers(path, line, tokens, 3, "vertex");
      ++n.positions;
    } else if (key == "vt") {
      checkObjNumbers(path, line, tokens, 2, "texture coordinate");
      ++n.texcoords;
    } else if (key == "vn") {
      checkObjNumbers(path, line, tokens, 3, "normal");
      ++n.normals;
    } else if (key == "f") {
      checkObjFace(path, line, tokens, n);
      ++n.faces;
      // A vertex used with two different vt: a seam (OpenMesh keeps one uv).
      for (size_t i = 1; i < tokens.size() && groups.seamLine == 0; ++i) {
        size_t a = tokens[i].find('/');
        if (a == std::string::npos) continue;
        size_t b = tokens[i].find('/', a + 1);
        std::string vt = tokens[i].substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
        int64_t v = 0, t = 0;
        if (vt.empty() || !meshcheck::parseInteger(tokens[i].substr(0, a), v) || !meshcheck::parseInteger(vt, t)) continue;
        if (v < 0) v += n.positions + 1;  // relative indices, checked above
        if (t < 0) t += n.texcoords + 1;
        auto [it, fresh] = vertexTexcoord.emplace(v, t);
        if (!fresh && it->second != t) groups.seamLine = line;
      }
      if (current < 0) {
        groups.names.push_back("");
        current = int(groups.names.size()) - 1;
      }
      groups.faceGroup.push_back(current);
      groups.faceVertices.push_back(int(tokens.size()) - 1);
    } else if (key == "usemtl") {
      std::string name = tokens.size() > 1 ? tokens[1] : "";
      auto it = std::find(groups.names.begin(), groups.names.end(), name);
      current = int(it - groups.names.begin());
      if (it == groups.names.end()) groups.names.push_back(name);
    } else if (key == "mtllib") {
      checkMaterialLibrary(path, line, trimmed);
    }
  }
  if (in.bad()) failAt(path, 0, "read error");
  if (n.faces == 0) failAt(path, 0, "no faces (no 'f' lines; " + std::to_string(n.positions) + " vertices)");
  return groups;
}

}  // namespace lb
