#pragma once
// Structural checks run on an OBJ or PLY file before OpenMesh parses it.
//
// OpenMesh 9.0's readers trust their input: an out-of-range face index, a face
// token without a vertex, a PLY header it cannot tokenize or a count larger than
// the file lead to aborts, heap corruption, endless loops or huge allocations.
// These checks are not a second parser (the mesh data still comes from
// OpenMesh); they scan the file once and refuse anything the reader would
// mishandle, so that a bad file is one clear error instead of a crash.
//
// Each check throws std::runtime_error with one line
// "PATH:LINE: what is wrong" (or "PATH: byte OFFSET: ..." for binary PLY data).
#include <cstdint>
#include <string>
#include <vector>

namespace lb {

// The `usemtl` group of every face of an OBJ file, in file order: what
// per-group materials need (OpenMesh reads the faces but not their groups).
struct ObjFaceGroups {
  std::vector<std::string> names;  // in order of first use; "" for faces before any usemtl
  std::vector<int> faceGroup;      // per `f` line: index into names
  std::vector<int> faceVertices;   // per `f` line: its vertex count (n − 2 triangles)
  uint64_t seamLine = 0;           // first line using a vertex with a second vt (a texture seam), or 0
};

ObjFaceGroups validateObjFile(const std::string& path);
void validatePlyFile(const std::string& path);

namespace meshcheck {

// Throws "path:line: message" (line 0: no line, "path: message").
[[noreturn]] void failAt(const std::string& path, uint64_t line, const std::string& message);
// A file token made safe to quote in a one-line message (printable, short).
std::string shown(const std::string& token);
// Whole-token parses, mirroring what the readers' stream extraction accepts.
bool parseInteger(const std::string& token, int64_t& value);  // [+-]digits, fits int64
bool parseFloat(const std::string& token, double& value);     // finite, within float range

}  // namespace meshcheck
}  // namespace lb
