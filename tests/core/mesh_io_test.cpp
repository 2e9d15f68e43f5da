// Malformed OBJ/PLY files are one clear error, never a crash, hang or huge
// allocation (issue 12); valid meshes still load. The reproducers live in
// tests/data/meshes/, each a file that once crashed or hung the loader (or a
// case of the same kind).
#include <gtest/gtest.h>
#include <unistd.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>
#include "core/mesh_io.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

std::string meshData(const std::string& name) { return test::sourcePath("tests/data/meshes/" + name); }

// A fresh folder for files the tests write.
std::filesystem::path scratch() {
  auto dir = std::filesystem::temp_directory_path() / ("lightbench_mesh_io_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}
std::string writeFile(const std::string& name, const std::string& bytes) {
  auto path = scratch() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// The error loadMesh throws for a file ("" if it loads).
std::string loadError(const std::string& path) {
  try {
    loadMesh(path, Mat4(1.f), false);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

struct BadMesh {
  const char* file;
  const char* where;   // ":LINE:" or "byte N"
  const char* phrase;  // what is wrong
};

class MeshBadFile : public testing::TestWithParam<BadMesh> {};

TEST_P(MeshBadFile, IsOneLineErrorNamingFileAndPlace) {
  const BadMesh& c = GetParam();
  std::string message = loadError(meshData(c.file));
  ASSERT_FALSE(message.empty()) << c.file << " loaded";
  EXPECT_NE(message.find(std::string(c.file) + (c.where[0] == ':' ? "" : ": ") + c.where), std::string::npos)
      << message;
  EXPECT_NE(message.find(c.phrase), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Reproducers, MeshBadFile,
    testing::Values(
        // The failures found by hand and by fuzzing.
        BadMesh{"obj_face_no_vertex.obj", ":1:", "face has 1 vertices (at least 3 needed)"},
        BadMesh{"obj_face_index_out_of_range.obj", ":4:", "vertex index 3 out of range (2 vertices)"},
        BadMesh{"ply_misspelled_element.ply", ":3:", "unknown PLY header keyword 'elemen'"},
        BadMesh{"ply_element_count_garbage.ply", ":3:", "element count 'p3' is not a non-negative integer"},
        BadMesh{"ply_element_count_not_number.ply", ":3:", "element count 'p3' is not a non-negative integer"},
        BadMesh{"ply_huge_vertex_count.ply", ":3:", "count 4000000000 needs more data than the"},
        // The same kinds of failure, in general.
        BadMesh{"obj_face_token_without_vertex.obj", ":4:", "face vertex '/1' is not v, v/vt, v//vn or v/vt/vn"},
        BadMesh{"ply_ascii_vertex_count_too_large.ply", ":3:", "count 5 needs more data than the"},
        BadMesh{"obj_index_zero.obj", ":4:", "index 0 (OBJ indices start at 1)"},
        BadMesh{"obj_negative_index_out_of_range.obj", ":4:", "vertex index -4 out of range (3 vertices)"},
        BadMesh{"obj_index_not_integer.obj", ":4:", "vertex index 'x' is not an integer"},
        BadMesh{"obj_index_huge.obj", ":4:", "is not an integer"},
        BadMesh{"obj_face_two_vertices.obj", ":4:", "face has 2 vertices (at least 3 needed)"},
        BadMesh{"obj_face_before_vertices.obj", ":1:", "vertex index 1 out of range (0 vertices)"},
        BadMesh{"obj_texcoord_out_of_range.obj", ":5:", "texture coordinate index 2 out of range (1 vt lines)"},
        BadMesh{"obj_normal_out_of_range.obj", ":5:", "normal index 2 out of range (1 vn lines)"},
        BadMesh{"obj_nan_coordinate.obj", ":2:", "'nan' is not a finite number"},
        BadMesh{"obj_vertex_two_numbers.obj", ":2:", "vertex needs 3 numbers, found 2"},
        BadMesh{"obj_crlf_out_of_range.obj", ":4:", "vertex index 4 out of range (3 vertices)"},
        BadMesh{"obj_no_faces.obj", "no faces", "no faces"},
        BadMesh{"ply_face_index_out_of_range.ply", ":13:", "face index 3 out of range (3 vertices)"},
        BadMesh{"ply_face_index_negative.ply", ":13:", "face index -1 out of range"},
        BadMesh{"ply_face_two_vertices.ply", ":13:", "face has 2 vertices (at least 3 needed)"},
        BadMesh{"ply_ascii_truncated.ply", ":14:", "file ends inside element 'face' (item 0 of 1)"},
        BadMesh{"ply_unknown_type.ply", ":6:", "unknown property type 'flaot'"},
        BadMesh{"ply_missing_z.ply", ":3:", "vertex element has no 'z' property"},
        BadMesh{"ply_face_before_vertex.ply", ":3:", "face element before the vertex element"},
        BadMesh{"ply_list_count_float.ply", ":8:", "list count type 'float' is not supported"},
        BadMesh{"ply_inf_coordinate.ply", ":11:", "value 'inf' is not a finite number"},
        BadMesh{"ply_no_end_header.ply", "PLY header", "has no end_header"},
        BadMesh{"ply_binary_truncated.ply", "byte 218", "file ends inside element 'face' (item 0 of 1)"},
        BadMesh{"ply_binary_huge_list_count.ply", "byte 219", "file ends inside element 'face'"},
        BadMesh{"ply_binary_face_index_out_of_range.ply", "byte 214", "face index 7 out of range (3 vertices)"}));

TEST(MeshBadFileTest, DirectoryEmptyFileAndMissingFileAreErrors) {
  auto dir = scratch() / "folder.obj";
  std::filesystem::create_directories(dir);
  EXPECT_NE(loadError(dir.string()).find("not a regular file"), std::string::npos);
  EXPECT_NE(loadError(writeFile("empty.ply", "")).find("file is empty"), std::string::npos);
  EXPECT_NE(loadError((scratch() / "missing.obj").string()).find("not found"), std::string::npos);
}

TEST(MeshBadFileTest, BinaryPlyHeaderTheReaderWouldMisplaceIsRefused) {
  // OpenMesh finds binary data 12 bytes after the token before end_header; after
  // a comment that is one byte late, so the data would be read shifted.
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 0\nproperty list uchar int vertex_indices\ncomment last\n"
                    "end_header\n";
  EXPECT_NE(loadError(writeFile("comment_last.ply", ply)).find("layout the mesh reader misreads"), std::string::npos);
}

TEST(MeshBadFileTest, ListPropertiesOtherThanFaceIndicesAreRefused) {
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "property list uchar float extra\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "end_header\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n";
  EXPECT_NE(loadError(writeFile("vertex_list.ply", ply)).find("list property 'extra' in element 'vertex' is not supported"),
            std::string::npos);
}

TEST(MeshValidFile, ShippedMeshesLoad) {
  for (const char* name : {"scenes/meshes/ring.obj", "scenes/meshes/water.obj"}) {
    MeshLoadResult r = loadMesh(test::sourcePath(name), Mat4(1.f), true);
    EXPECT_GT(r.mesh.triangles.size(), 0u) << name;
  }
}

TEST(MeshValidFile, ObjWithNegativeIndicesQuadsTexcoordsAndNormals) {
  std::string obj = "# a quad and a triangle\r\n"
                    "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
                    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                    "f -4/-4/-1 -3/-3/-1 -2/-2/-1 -1/-1/-1\n"
                    "v 0 0 1\n"
                    "f 2/2/1 1/1/1 -1/3/1\n";  // edge 2-1 runs opposite to the quad's 1-2
  MeshLoadResult r = loadMesh(writeFile("valid.obj", obj), Mat4(1.f), false);
  EXPECT_EQ(r.mesh.triangles.size(), 3u);  // the quad triangulated by OpenMesh, and the triangle
  EXPECT_EQ(r.mesh.positions.size(), 5u);
  EXPECT_EQ(r.mesh.uvs.size(), 5u);
  EXPECT_EQ(r.mesh.normals.size(), 5u);
}

TEST(MeshValidFile, AsciiPlyWithCommentsAndCrlf) {
  std::string ply = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 4\r\nproperty float x\r\n"
                    "property float y\r\nproperty float z\r\nelement face 1\r\n"
                    "property list uchar int vertex_indices\r\nend_header\r\n"
                    "0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n";
  EXPECT_EQ(loadMesh(writeFile("valid_ascii.ply", ply), Mat4(1.f), false).mesh.triangles.size(), 2u);
}

// A binary PLY with a quad and a triangle, in either byte order, its header
// lines ending in "\n" or "\r\n".
std::string binaryPly(bool bigEndian, bool crlf = false) {
  std::string out = std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment written by mesh_io_test\nelement vertex 5\nproperty float x\nproperty float y\n"
                    "property float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\n"
                    "end_header\n";
  if (crlf)
    for (size_t at = 0; (at = out.find('\n', at)) != std::string::npos; at += 2) out.insert(at, "\r");
  auto put = [&](const void* p, size_t n) {
    std::string bytes(static_cast<const char*>(p), n);
    if (bigEndian) bytes.assign(bytes.rbegin(), bytes.rend());
    out += bytes;
  };
  const float xyz[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& v : xyz) {
    for (float c : v) put(&c, 4);
    out += char(200);
  }
  for (const std::vector<int32_t>& face : {std::vector<int32_t>{0, 1, 2, 3}, std::vector<int32_t>{1, 0, 4}}) {
    out += char(face.size());
    for (int32_t i : face) put(&i, 4);
  }
  return out;
}

TEST(MeshValidFile, BinaryPlyBothByteOrders) {
  for (bool bigEndian : {false, true}) {
    MeshLoadResult r = loadMesh(writeFile(bigEndian ? "be.ply" : "le.ply", binaryPly(bigEndian)), Mat4(1.f), false);
    EXPECT_EQ(r.mesh.triangles.size(), 3u) << bigEndian;
    EXPECT_EQ(r.mesh.positions.size(), 5u) << bigEndian;
    EXPECT_EQ(r.mesh.positions[2], Vec3(1, 1, 0)) << bigEndian;
  }
  MeshLoadResult crlf = loadMesh(writeFile("crlf.ply", binaryPly(false, true)), Mat4(1.f), false);
  EXPECT_EQ(crlf.mesh.triangles.size(), 3u);
  EXPECT_EQ(crlf.mesh.positions[2], Vec3(1, 1, 0));
}

}  // namespace
}  // namespace lb
