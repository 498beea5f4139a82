// read_obj: accepted syntax, attributes, and every error with its line.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

using test::throws_file_error;

TriMesh obj(const std::string& s) { return read_obj(s, "m.obj"); }

::testing::AssertionResult obj_error(const std::string& s, std::uint64_t line, std::string_view reason) {
  return throws_file_error([&] { (void)read_obj(s, "m.obj"); }, "m.obj", FileLocation::line(line), reason);
}

const std::string kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

TEST(ObjReader, SingleTriangle) {
  const TriMesh m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ASSERT_EQ(m.vertex_count(), 3u);
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.positions[1], Vec3(1, 0, 0));
  EXPECT_TRUE(m.normals.empty());
  EXPECT_TRUE(m.texcoords.empty());
  EXPECT_TRUE(m.indices_valid());
}

TEST(ObjReader, NumbersAreParsedExactly) {
  const TriMesh m = obj("v 0.1 -2.5e-3 +1E2\nv 1e-400 -0 12345678901234567890\nv .5 5. -.25\nf 1 2 3\n");
  EXPECT_EQ(m.positions[0], Vec3(0.1, -2.5e-3, 100.0));
  EXPECT_EQ(m.positions[1], Vec3(0.0, -0.0, 12345678901234567890.0));  // 1e-400 underflows to 0
  EXPECT_EQ(m.positions[2], Vec3(0.5, 5.0, -0.25));
}

TEST(ObjReader, AllCornerForms) {
  const std::string head = kSquare + "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvn 0 0 -1\n";
  for (const std::string face : {"f 1 2 3", "f 1/1 2/2 3/3", "f 1//1 2//1 3//2", "f 1/1/1 2/2/1 3/3/2"}) {
    SCOPED_TRACE(face);
    const TriMesh m = obj(head + face + "\n");
    ASSERT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.vertex_count(), 4u);
  }
  const TriMesh m = obj(head + "f 1/1/1 2/2/1 3/3/2\n");
  ASSERT_EQ(m.texcoords.size(), 3u);
  EXPECT_EQ(m.texcoords[1], Vec2(1, 0));
  EXPECT_EQ(m.texcoords[2], Vec2(1, 1));
  ASSERT_EQ(m.normals.size(), 4u);
  EXPECT_EQ(m.normals[0], Vec3(0, 0, 1));
  EXPECT_EQ(m.normals[2], Vec3(0, 0, -1));
  EXPECT_EQ(m.normals[3], Vec3::Zero());  // unused vertex
}

TEST(ObjReader, NegativeIndicesAreRelative) {
  const TriMesh m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -1 -2\n");
  ASSERT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 3, 2}));
}

TEST(ObjReader, PolygonsAreFanTriangulated) {
  const TriMesh m = obj(kSquare + "v 0.5 2 0\nf 1 2 3 5 4\n");
  ASSERT_EQ(m.triangle_count(), 3u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 4}));
  EXPECT_EQ(m.triangles[2], (Triangle{0, 4, 3}));
}

TEST(ObjReader, WhitespaceCommentsCrlfBom) {
  const std::string s =
      "\xEF\xBB\xBF# comment\r\n\r\n  v\t0 0 0  # trailing\r\nv 1 0 0\r\n\tv 0 1 0\r\n"
      "f  1\t2 3 \r\n# end";
  const TriMesh m = obj(s);
  EXPECT_EQ(m.vertex_count(), 3u);
  EXPECT_EQ(m.triangle_count(), 1u);
}

TEST(ObjReader, LineContinuation) {
  const TriMesh m = obj("v 0 0 \\\n 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\n 3\nv 9 9 9\n");
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.positions[0], Vec3(0, 0, 0));
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  // An error inside a continued statement names its first line.
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 \\\n x 0\nf 1 2 3\n", 2, "'x' is not a number"));
  // ...and later lines keep their own numbers.
  EXPECT_TRUE(obj_error("v 0 0 \\\n0\nv 1 0 0\nv 1 0 nan\n", 4, "not finite"));
}

TEST(ObjReader, OtherStatementsAreIgnored) {
  const std::string s =
      "mtllib liver.mtl\no obj\ng default group\ns 1\ns off\nusemtl skin\nvp 0.5\n"
      "cstype bezier\nfoo bar 1 2\n" +
      kSquare + "l 1 2 3\np 1\nf 1 2 3\n";
  const TriMesh m = obj(s);
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.triangle_count(), 1u);
}

TEST(ObjReader, OptionalWAndVertexColours) {
  const TriMesh m = obj("v 0 0 0 1\nv 1 0 0 0.5 0.2 0.3\nv 0 1 0 1 0.5 0.2 0.3\nf 1 2 3\n");
  EXPECT_EQ(m.positions[2], Vec3(0, 1, 0));
}

TEST(ObjReader, UnusedVerticesAndOrderKept) {
  const TriMesh m = obj("v 9 9 9\n" + kSquare + "v 8 8 8\nf 2 3 4\n");
  ASSERT_EQ(m.vertex_count(), 6u);
  EXPECT_EQ(m.positions[0], Vec3(9, 9, 9));
  EXPECT_EQ(m.positions[5], Vec3(8, 8, 8));
  EXPECT_EQ(m.triangles[0], (Triangle{1, 2, 3}));
}

TEST(ObjReader, NormalOfFirstReferencingCorner) {
  // Vertex 1 is referenced with normal 2 first, then with normal 1: it keeps normal 2.
  const TriMesh m = obj(kSquare + "vn 1 0 0\nvn 0 1 0\nvn 0 0 1\nf 1//2 2//3 3//3\nf 1//1 3//1 4//1\n");
  ASSERT_EQ(m.normals.size(), 4u);
  EXPECT_EQ(m.normals[0], Vec3(0, 1, 0));
  EXPECT_EQ(m.normals[1], Vec3(0, 0, 1));
  EXPECT_EQ(m.normals[2], Vec3(0, 0, 1));
  EXPECT_EQ(m.normals[3], Vec3(1, 0, 0));
}

TEST(ObjReader, AttributesDroppedUnlessEveryCornerHasThem) {
  const std::string head = kSquare + "vt 0 0\nvt 1 1\nvn 0 0 1\n";
  const TriMesh m = obj(head + "f 1/1/1 2/2/1 3/1/1\nf 1 3 4\n");
  EXPECT_TRUE(m.normals.empty());
  EXPECT_TRUE(m.texcoords.empty());
  EXPECT_EQ(m.triangle_count(), 2u);
  const TriMesh n = obj(head + "f 1//1 2//1 3//1\n");  // normals yes, texcoords no
  EXPECT_EQ(n.normals.size(), 4u);
  EXPECT_TRUE(n.texcoords.empty());
  const TriMesh t = obj(head + "f 1/1 2/2 3/1 4/2\n");  // texcoords per corner of both triangles
  ASSERT_EQ(t.texcoords.size(), 6u);
  EXPECT_EQ(t.texcoords[3], Vec2(0, 0));
  EXPECT_EQ(t.texcoords[4], Vec2(0, 0));
  EXPECT_EQ(t.texcoords[5], Vec2(1, 1));
  EXPECT_TRUE(t.indices_valid());
}

TEST(ObjReader, TexcoordWithOneOrThreeNumbers) {
  const TriMesh m = obj("vt 0.5\nvt 0.25 0.75 1\n" + kSquare + "f 1/1 2/2 3/1\n");
  ASSERT_EQ(m.texcoords.size(), 3u);
  EXPECT_EQ(m.texcoords[0], Vec2(0.5, 0));
  EXPECT_EQ(m.texcoords[1], Vec2(0.25, 0.75));
}

TEST(ObjReader, ForwardReferencesAreResolvedAtTheEnd) {
  const TriMesh m = obj("f 1 2 3\n" + kSquare);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
}

// ---- errors ----

TEST(ObjReaderErrors, EmptyAndFacelessFiles) {
  EXPECT_TRUE(throws_file_error([] { (void)obj(""); }, "m.obj", FileLocation::none(), "empty file"));
  EXPECT_TRUE(throws_file_error([] { (void)obj("\n  \n# only a comment\n"); }, "m.obj",
                                FileLocation::none(), "no triangles"));
  EXPECT_TRUE(throws_file_error([] { (void)obj(kSquare + "l 1 2\n"); }, "m.obj", FileLocation::none(),
                                "no triangles (4 vertices"));
}

TEST(ObjReaderErrors, IndexOutOfRange) {
  EXPECT_TRUE(obj_error(kSquare + "f 1 2 3\nf 1 2 5\n", 6, "vertex index 5 is out of range (the file has 4 'v')"));
  EXPECT_TRUE(obj_error(kSquare + "f 1 0 3\n", 5, "vertex index 0"));
  EXPECT_TRUE(obj_error(kSquare + "f 1 2 -5\n", 5, "relative vertex index -5"));
  EXPECT_TRUE(obj_error(kSquare + "f 1 2 99999999999999999999\n", 5, "out of range"));
  EXPECT_TRUE(obj_error(kSquare + "f 1 2 4294967295\n", 5, "out of range"));
  EXPECT_TRUE(obj_error(kSquare + "f 1 2 x\n", 5, "'x' is not an integer"));
  EXPECT_TRUE(obj_error(kSquare + "f 1 2 3.0\n", 5, "is not an integer"));
}

TEST(ObjReaderErrors, MissingTexcoordsOrNormals) {
  EXPECT_TRUE(obj_error(kSquare + "vt 0 0\nf 1/1 2/2 3/1\n", 6, "texture coordinate index 2 is out of range"));
  EXPECT_TRUE(obj_error(kSquare + "f 1//1 2//1 3//1\n", 5, "normal index 1 is out of range (the file has 0 'vn')"));
  EXPECT_TRUE(obj_error(kSquare + "vn 0 0 1\nf 1//1 2//-2 3//1\n", 6, "relative normal index -2"));
}

TEST(ObjReaderErrors, BadFaces) {
  EXPECT_TRUE(obj_error(kSquare + "f 1 2\n", 5, "'f' with 2 vertices"));
  EXPECT_TRUE(obj_error(kSquare + "f\n", 5, "'f' with 0 vertices"));
  EXPECT_TRUE(obj_error(kSquare + "f 1/1/1/1 2 3\n", 5, "is not v, v/t, v//n or v/t/n"));
  EXPECT_TRUE(obj_error(kSquare + "f 1// 2 3\n", 5, "is not v, v/t, v//n or v/t/n"));
  EXPECT_TRUE(obj_error(kSquare + "f 1/ 2 3\n", 5, "is not v, v/t, v//n or v/t/n"));
  EXPECT_TRUE(obj_error(kSquare + "f /1 2 3\n", 5, "has no vertex index"));
}

TEST(ObjReaderErrors, BadNumbers) {
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 0\nf 1 2 3\n", 2, "'v' needs 3 coordinates x y z, got 2"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 0 abc\n", 2, "'v': 'abc' is not a number"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 0 1.5.5\n", 2, "'1.5.5' is not a number"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 0 nan\n", 2, "'nan' is not finite"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 -inf 0\n", 2, "'-inf' is not finite"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 1e400 0\n", 2, "'1e400' is out of range"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1 2 3 4 5 6 7 8\n", 2, "at most 7"));
  EXPECT_TRUE(obj_error("vn 0 0\n", 1, "'vn' needs 3 numbers"));
  EXPECT_TRUE(obj_error("vn 0 0 1 1\n", 1, "'vn' needs 3 numbers"));
  EXPECT_TRUE(obj_error("vn 0 NaN 1\n", 1, "not finite"));
  EXPECT_TRUE(obj_error("vt\n", 1, "'vt' needs 1 to 3 numbers"));
  EXPECT_TRUE(obj_error("vt 0 0 0 0\n", 1, "'vt' needs 1 to 3 numbers"));
  EXPECT_TRUE(obj_error("vt 0 u\n", 1, "'u' is not a number"));
  EXPECT_TRUE(obj_error("v 0 0 0\nv 1,5 0 0\n", 2, "'1,5' is not a number"));
}

TEST(ObjReaderErrors, BinaryGarbage) {
  EXPECT_TRUE(obj_error(kSquare + std::string("f 1 2 3\nv 1 2\x00 3\n", 17), 6, "binary data"));
  std::string garbage;
  for (int i = 0; i < 256; ++i) garbage += static_cast<char>(i * 7 + 3);
  EXPECT_TRUE(obj_error(garbage, 1, "binary data"));
  // A binary STL handed to the OBJ reader.
  const std::string stl = test::make_binary_stl({{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}}, std::string("hdr\0", 4));
  EXPECT_TRUE(obj_error(stl, 1, "not a text OBJ file"));
}

TEST(ObjReaderErrors, MessageQuotesUnprintableTokens) {
  try {
    (void)obj("v 0 0 \xff\xfe\n");
    FAIL() << "no throw";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("'\\xff\\xfe' is not a number"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trocar
