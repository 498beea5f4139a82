// read_ply: ascii and both binary byte orders, every scalar type, skipped elements and
// properties, assimp as an oracle, and every malformed-input error with its line or byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

#if TROCAR_HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

namespace trocar {
namespace {

TriMesh ply(const std::string& s) { return read_ply(s, "m.ply"); }

/// Passes when reading `text` throws FileError naming m.ply, exactly `where`, and `reason`.
::testing::AssertionResult ply_error(const std::string& text, FileLocation where, const std::string& reason) {
  return test::throws_file_error([&] { (void)read_ply(text, "m.ply"); }, "m.ply", where, reason);
}

FileLocation line(std::uint64_t l) { return FileLocation::line(l); }
FileLocation byte(std::uint64_t b) { return FileLocation::byte(b); }

/// Appends the bytes of `value` in the requested byte order.
template <class T>
void put(std::string& out, T value, bool big) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

const char* kFormatName[3] = {"ascii", "binary_little_endian", "binary_big_endian"};

/// A PLY with float x y z and faces as `list uchar int vertex_indices`; format 0 ascii,
/// 1 little-endian, 2 big-endian. `header_only` gives just the header (for offsets).
std::string make_ply(int format, const std::vector<Vec3>& v, const std::vector<std::vector<int>>& faces,
                     bool header_only = false) {
  std::string out = std::string("ply\nformat ") + kFormatName[format] + " 1.0\nelement vertex " +
                    std::to_string(v.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  if (header_only) return out;
  for (const Vec3& p : v) {
    if (format == 0) {
      out += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
    } else {
      for (int k = 0; k < 3; ++k) put(out, static_cast<float>(p[k]), format == 2);
    }
  }
  for (const auto& f : faces) {
    if (format == 0) {
      out += std::to_string(f.size());
      for (int i : f) out += " " + std::to_string(i);
      out += "\n";
    } else {
      put(out, static_cast<std::uint8_t>(f.size()), false);
      for (int i : f) put(out, static_cast<std::int32_t>(i), format == 2);
    }
  }
  return out;
}

const std::vector<Vec3> kSquare = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
const std::vector<std::vector<int>> kFaces = {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}};

TEST(PlyReader, AllThreeFormatsGiveTheSameMesh) {
  for (int format = 0; format < 3; ++format) {
    const TriMesh m = ply(make_ply(format, kSquare, kFaces));
    ASSERT_EQ(m.vertex_count(), 5u) << format;
    ASSERT_EQ(m.triangle_count(), 4u) << format;
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
    EXPECT_EQ(m.triangles[3], (Triangle{1, 2, 4}));
    EXPECT_EQ(m.positions[4], Vec3(0.5, 0.5, 1)) << format;
    EXPECT_TRUE(m.normals.empty());
    EXPECT_TRUE(m.indices_valid());
  }
}

TEST(PlyReader, AsciiWithNormalsCommentsAndSkippedData) {
  const TriMesh m = ply(
      "ply\r\nformat ascii 1.0\r\ncomment made by hand\nobj_info nothing\n"
      "element material 1\nproperty list uchar float coeffs\nproperty uchar id\n"
      "element vertex 3\nproperty double x\nproperty float64 y\nproperty float32 z\n"
      "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
      "property list int uint extra\n"
      "element face 2\nproperty uchar flags\nproperty list uint8 uint32 vertex_index\n"
      "property list ushort float texcoord\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\r\n"
      "3 0.5 0.25 1 7\n"
      "0.1 0 0  0 0 1 255  2 9 9\n"
      "1 0 0  0 0 1 0 0\n"
      "0 1e0 -0 0 0 1 0 1 4\n"
      "1 3 0 1 2 6 0 0 1 0 0 1\n"
      "0 0 0\n"
      "0 1\n");
  ASSERT_EQ(m.vertex_count(), 3u);
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.positions[0], Vec3(0.1, 0, 0));  // double property: exact
  ASSERT_EQ(m.normals.size(), 3u);
  EXPECT_EQ(m.normals[2], Vec3(0, 0, 1));
}

TEST(PlyReader, EveryScalarTypeInBinary) {
  for (bool big : {false, true}) {
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 3\nproperty char a\nproperty int16 b\nproperty ushort c\n"
                    "property uint d\nproperty double x\nproperty int y\nproperty short z\n"
                    "element face 2\nproperty list int8 uint16 vertex_indices\nproperty list char double junk\n"
                    "end_header\n";
    for (int i = 0; i < 3; ++i) {
      put(s, std::int8_t{-5}, big);
      put(s, std::int16_t{-300}, big);
      put(s, std::uint16_t{60000}, big);
      put(s, std::uint32_t{4000000000u}, big);
      put(s, 0.1 * i, big);
      put(s, std::int32_t{-100000 * i}, big);
      put(s, static_cast<std::int16_t>(-i), big);
    }
    put(s, std::int8_t{3}, big);
    for (int k = 0; k < 3; ++k) put(s, static_cast<std::uint16_t>(k), big);
    put(s, std::int8_t{1}, big);
    put(s, 2.5, big);
    put(s, std::int8_t{0}, big);  // an empty face is dropped
    put(s, std::int8_t{0}, big);
    const TriMesh m = ply(s);
    ASSERT_EQ(m.vertex_count(), 3u);
    ASSERT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.positions[2], Vec3(0.2, -200000, -2));
  }
}

TEST(PlyReader, NonFiniteValuesInOtherPropertiesAreIgnored) {
  const TriMesh m = ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                        "property float nx\nproperty float ny\nproperty float nz\nproperty float quality\n"
                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                        "0 0 0 0 0 1 nan\n1 0 0 0 0 1 inf\n0 1 0 0 0 1 1\n3 0 1 2\n");
  EXPECT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.normals.size(), 3u);
}

TEST(PlyReader, FaceElementMayComeFirst) {
  const TriMesh m = ply("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                        "3 2 1 0\n0 0 0\n1 0 0\n0 1 0\n");
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{2, 1, 0}));
}

TEST(PlyReader, IntegerValuesAreRangeChecked) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty uchar x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string rest = "0 1 0\n0 0 1\n3 0 1 2\n";  // lines 11-13: two more vertices, one face
  EXPECT_EQ(ply(head + "255 0 0\n" + rest).positions[0], Vec3(255, 0, 0));
  EXPECT_TRUE(ply_error(head + "256 0 0\n" + rest, line(10), "out of range for its type"));
  EXPECT_TRUE(ply_error(head + "1.5 0 0\n" + rest, line(10), "bad integer"));
}

TEST(PlyReader, APointCloudIsNotASurface) {
  // Valid PLY with vertices and no faces: an error like the other readers' "no triangles".
  const std::string cloud = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_THROW(ply(cloud), FileError);
  try {
    ply(cloud);
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
  }
}

#if TROCAR_HAVE_ASSIMP
using Corners = std::array<std::array<float, 3>, 3>;

std::vector<Corners> sorted(std::vector<Corners> tris) {
  for (Corners& c : tris) std::sort(c.begin(), c.end());
  std::sort(tris.begin(), tris.end());
  return tris;
}

std::vector<Corners> ours(const TriMesh& m) {
  std::vector<Corners> out;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const auto p = m.corners(t);
    Corners c;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) c[i][k] = static_cast<float>(p[i][k]);
    out.push_back(c);
  }
  return sorted(out);
}

std::vector<Corners> assimp(const std::string& bytes) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_Triangulate, "ply");
  EXPECT_NE(scene, nullptr) << importer.GetErrorString();
  std::vector<Corners> out;
  if (!scene) return out;
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* mesh = scene->mMeshes[mi];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      Corners c;
      for (int i = 0; i < 3; ++i) {
        const aiVector3D& v = mesh->mVertices[face.mIndices[i]];
        c[i] = {v.x, v.y, v.z};
      }
      out.push_back(c);
    }
  }
  return sorted(out);
}

TEST(PlyReaderAssimp, SmallMeshesAgreeWithAssimp) {
  for (int format = 0; format < 3; ++format) {
    const std::string bytes = make_ply(format, kSquare, kFaces);
    EXPECT_EQ(ours(ply(bytes)), assimp(bytes)) << kFormatName[format];
  }
}

TEST(PlyReaderAssimp, LiverAgreesWithAssimp) {
  // The liver, via the VRML copy of the SOFA mesh, written as PLY in each format.
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.wrl");
  const TriMesh liver = load_mesh(path);
  std::vector<std::vector<int>> faces;
  for (const Triangle& t : liver.triangles)
    faces.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
  for (int format = 0; format < 3; ++format) {
    const std::string bytes = make_ply(format, liver.positions, faces);
    const TriMesh m = ply(bytes);
    ASSERT_EQ(m.triangles, liver.triangles);
    const std::vector<Corners> a = ours(m), b = assimp(bytes);
    ASSERT_EQ(a.size(), 4384u);
    ASSERT_EQ(b.size(), a.size());
    // assimp's ascii number parser is not always correctly rounded: allow a float ulp or two.
    for (std::size_t t = 0; t < a.size(); ++t)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(a[t][i][k], b[t][i][k], 1e-6f * std::max(1.0f, std::abs(a[t][i][k]))) << kFormatName[format];
  }
}
#endif

// --- errors -----------------------------------------------------------------------------------

TEST(PlyReaderErrors, Header) {
  EXPECT_TRUE(ply_error("", line(1), "not a PLY file"));
  EXPECT_TRUE(ply_error("plyx\n", line(1), "not a PLY file"));
  EXPECT_TRUE(ply_error("ply\nformat binary_middle_endian 1.0\nend_header\n", line(2), "unknown PLY format"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 2.0\nend_header\n", line(2), "unsupported PLY version"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 3\n", line(4), "no end_header"));
  EXPECT_TRUE(ply_error("ply\nend_header\n", line(2), "no format line"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n", line(3), "property before any element"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", line(4), "unknown property type"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n", line(4),
                        "list count type"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", line(3), "bad element count"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\nend_header\n", line(4), "declared twice"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nbogus\nend_header\n", line(3), "unknown header keyword"));
}

TEST(PlyReaderErrors, MissingElementsOrProperties) {
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
                        FileLocation::none(), "no 'vertex' element"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nend_header\n",
                        FileLocation::none(), "no 'face' element"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                        "element face 0\nproperty list uchar int vertex_indices\nend_header\n", line(3), "'z'"));
  EXPECT_TRUE(ply_error("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                        "element face 0\nproperty int vertex_indices\nend_header\n", line(7), "no list property"));
}

TEST(PlyReaderErrors, LyingElementCountIsCaughtBeforeAllocating) {
  // Claims 4 billion vertices (48 GB of floats) in a few bytes: rejected at the header line.
  std::string s = make_ply(1, kSquare, kFaces);
  s.replace(s.find("vertex 5"), 8, "vertex 4000000000");
  EXPECT_TRUE(ply_error(s, line(3), "declares 4000000000 items"));
  std::string a = make_ply(0, kSquare, kFaces);
  a.replace(a.find("face 3"), 6, "face 300000000000");
  EXPECT_TRUE(ply_error(a, line(7), "declares 300000000000 items"));
  std::string other = make_ply(2, kSquare, kFaces);
  other.replace(other.find("end_header"), 10, "element junk 18446744073709551615\nproperty list uint char x\nend_header");
  EXPECT_TRUE(ply_error(other, line(9), "bytes remain"));
}

TEST(PlyReaderErrors, IndexOutOfRange) {
  std::vector<std::vector<int>> bad = kFaces;
  bad[1][2] = 5;
  EXPECT_TRUE(ply_error(make_ply(0, kSquare, bad), line(16), "vertex index 5 out of range (5 vertices)"));
  const std::size_t header = make_ply(1, kSquare, bad, true).size();
  // Face 1's third index: after 5 vertices (12 bytes each) and face 0 (1 + 16 bytes), 1 + 8.
  EXPECT_TRUE(ply_error(make_ply(1, kSquare, bad), byte(header + 60 + 17 + 9), "out of range"));
  bad[1][2] = -1;
  const std::size_t header_be = make_ply(2, kSquare, bad, true).size();
  EXPECT_TRUE(ply_error(make_ply(2, kSquare, bad), byte(header_be + 60 + 17 + 9), "vertex index -1 out of range"));
}

TEST(PlyReaderErrors, NegativeListCount) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list char int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_TRUE(ply_error(head + "-3 0 1 2\n", line(13), "negative list count"));
  std::string bin = make_ply(1, kSquare, kFaces);
  bin.replace(bin.find("list uchar"), 10, "list char ");
  const std::size_t header = bin.find("end_header\n") + 11;
  bin[header + 60] = static_cast<char>(-4);
  EXPECT_TRUE(ply_error(bin, byte(header + 60), "negative list count"));
}

TEST(PlyReaderErrors, NotANumber) {
  std::string a = make_ply(0, kSquare, kFaces);
  a.replace(a.find("0.500000 0.500000 1.000000"), 8, "nan");
  EXPECT_TRUE(ply_error(a, line(14), "not a finite number"));
  std::vector<Vec3> v = kSquare;
  v[2].y() = std::numeric_limits<double>::quiet_NaN();
  const std::size_t header = make_ply(2, v, kFaces, true).size();
  EXPECT_TRUE(ply_error(make_ply(2, v, kFaces), byte(header + 28), "not a finite number"));
  std::string word = make_ply(0, kSquare, kFaces);
  word.replace(word.find("0.500000 0.500000 1.000000"), 8, "half");
  EXPECT_TRUE(ply_error(word, line(14), "bad number 'half'"));
}

TEST(PlyReaderErrors, TruncatedBody) {
  const std::string a = make_ply(0, kSquare, kFaces);
  EXPECT_TRUE(ply_error(a.substr(0, a.size() - 3), line(17), "truncated"));
  const std::string b = make_ply(1, kSquare, kFaces);
  EXPECT_TRUE(ply_error(b.substr(0, b.size() - 2), byte(b.size() - 4), "truncated"));
  // Every prefix of a valid file is rejected cleanly (or, for the full file, read).
  for (int format = 0; format < 3; ++format) {
    const std::string s = make_ply(format, kSquare, kFaces);
    const std::size_t full = format == 0 ? s.size() - 1 : s.size();  // ascii: the final newline is optional
    for (std::size_t n = 0; n < full; ++n) EXPECT_THROW((void)ply(s.substr(0, n)), FileError) << n;
  }
}

}  // namespace
}  // namespace trocar
