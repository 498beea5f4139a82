// read_stl: binary/ASCII detection, welding, and every error with its byte offset or line.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

using test::Facet;
using test::make_binary_stl;
using test::throws_file_error;

TriMesh stl(const std::string& s) { return read_stl(s, "m.stl"); }

::testing::AssertionResult stl_error(const std::string& s, FileLocation where, std::string_view reason) {
  return throws_file_error([&] { (void)read_stl(s, "m.stl"); }, "m.stl", where, reason);
}

// Two triangles sharing the edge (1,0,0)-(0,1,0).
const std::vector<Facet> kTwo = {{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{1, 0, 0}, {1, 1, 0}, {0, 1, 0}}}};

const std::string kAsciiTwo =
    "solid two\n"
    "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
    "      vertex 0 1 0\n    endloop\n  endfacet\n"
    "  facet normal 0 0 1\n    outer loop\n      vertex 1 0 0\n      vertex 1 1 0\n"
    "      vertex 0 1 0\n    endloop\n  endfacet\n"
    "endsolid two\n";

void expect_two(const TriMesh& m) {
  ASSERT_EQ(m.vertex_count(), 4u);
  ASSERT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.positions[0], Vec3(0, 0, 0));
  EXPECT_EQ(m.positions[1], Vec3(1, 0, 0));
  EXPECT_EQ(m.positions[2], Vec3(0, 1, 0));
  EXPECT_EQ(m.positions[3], Vec3(1, 1, 0));
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{1, 3, 2}));
  EXPECT_TRUE(m.normals.empty());
  EXPECT_TRUE(m.texcoords.empty());
}

TEST(StlReader, BinaryWeldsInOrderOfFirstAppearance) { expect_two(stl(make_binary_stl(kTwo))); }

TEST(StlReader, BinaryWithSolidHeaderAndAttributes) {
  expect_two(stl(make_binary_stl(kTwo, "solid but actually binary", -1, 0xBEEF)));
}

TEST(StlReader, BinaryFloatValuesKept) {
  const float tiny = std::numeric_limits<float>::denorm_min();
  const TriMesh m = stl(make_binary_stl({{{{0.1f, -3.5e30f, tiny}, {1, 0, 0}, {0, 1, 0}}}}));
  EXPECT_EQ(m.positions[0], Vec3(double{0.1f}, double{-3.5e30f}, double{tiny}));
}

TEST(StlReader, NegativeZeroWeldsWithZero) {
  const TriMesh m = stl(make_binary_stl({{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {{{-0.0f, 0, -0.0f}, {0, 1, 0}, {0, 0, 1}}}}));
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
}

TEST(StlReader, DegenerateFacetsAreKept) {
  const TriMesh m = stl(make_binary_stl({{{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}}}, {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}}));
  ASSERT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 0, 1}));
  EXPECT_EQ(m.vertex_count(), 3u);
}

TEST(StlReader, Ascii) { expect_two(stl(kAsciiTwo)); }

TEST(StlReader, AsciiFreeFormAndMultipleSolids) {
  const std::string s =
      "\r\n  SOLID my part name\r\nFACET NORMAL 0 0 1 OUTER LOOP\r\n\tVERTEX 0 0 0 VERTEX 1 0 0\r\n"
      "vertex 0 1 0 endloop endfacet\r\nENDSOLID my part name\r\n"
      "solid\nfacet normal nan 0 0\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\n"
      "endfacet\nendsolid";
  expect_two(stl(s));
}

TEST(StlReader, AsciiExactNumbers) {
  const TriMesh m = stl("solid\nfacet normal 0 0 0\nouter loop\nvertex 0.1 +2e-3 -1E+2\n"
                        "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n");
  EXPECT_EQ(m.positions[0], Vec3(0.1, 2e-3, -100.0));
}

// ---- binary errors ----

TEST(StlReaderErrors, EmptyAndTooShort) {
  EXPECT_TRUE(stl_error("", FileLocation::none(), "empty file"));
  EXPECT_TRUE(stl_error(std::string(50, '\0'), FileLocation::none(), "too short for a binary STL (50 bytes"));
  EXPECT_TRUE(stl_error("hello", FileLocation::none(), "not an STL file"));
}

TEST(StlReaderErrors, ZeroFacets) {
  EXPECT_TRUE(stl_error(make_binary_stl({}), FileLocation::byte(80), "no triangles"));
}

TEST(StlReaderErrors, LyingCount) {
  std::string truncated = make_binary_stl(kTwo);
  truncated.resize(truncated.size() - 7);
  EXPECT_TRUE(stl_error(truncated, FileLocation::byte(80), "facet count 2 needs 184 bytes but the file has 177"));
  EXPECT_TRUE(stl_error(make_binary_stl(kTwo) + "x", FileLocation::byte(80), "trailing data"));
  EXPECT_TRUE(stl_error(make_binary_stl(kTwo, "test", 3), FileLocation::byte(80), "facet count 3"));
}

TEST(StlReaderErrors, HugeCountInSmallFileAllocatesNothing) {
  // 2^31 facets claimed (about 107 GB), 100 bytes present.
  std::string s = make_binary_stl({}, "test", 0x80000000LL);
  s.resize(100, '\0');
  EXPECT_TRUE(stl_error(s, FileLocation::byte(80), "facet count 2147483648 needs 107374182484 bytes but the file has 100"));
  s = make_binary_stl({}, "test", 0xFFFFFFFFLL);
  s.resize(100, '\0');
  EXPECT_TRUE(stl_error(s, FileLocation::byte(80), "facet count 4294967295"));
}

TEST(StlReaderErrors, BinaryNonFiniteNamesTheFacetOffset) {
  std::vector<Facet> facets = kTwo;
  facets.push_back({{{0, 0, 1}, {1, 0, 1}, {0, std::numeric_limits<float>::quiet_NaN(), 1}}});
  EXPECT_TRUE(stl_error(make_binary_stl(facets), FileLocation::byte(84 + 2 * 50), "facet 2 has a non-finite"));
  facets[2][2][1] = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(stl_error(make_binary_stl(facets), FileLocation::byte(184), "non-finite"));
  facets[2][2][1] = 0;
  facets[0][0][0] = -std::numeric_limits<float>::infinity();
  EXPECT_TRUE(stl_error(make_binary_stl(facets), FileLocation::byte(84), "facet 0"));
}

TEST(StlReaderErrors, SolidHeaderWithWrongCountMentionsBinary) {
  std::string s = make_binary_stl(kTwo, std::string("solid x\n\0\0\0", 11));
  s.resize(s.size() - 10);
  EXPECT_TRUE(stl_error(s, FileLocation::line(2), "holds binary data; read as binary STL, the facet count 2 at byte 80"));
}

// ---- ASCII errors ----

std::string replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

TEST(StlReaderErrors, AsciiStructure) {
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "    endloop\n  endfacet\n  facet", "    endloop\n  facet"), FileLocation::line(8),
                        "expected 'endfacet', got 'facet'"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "outer loop\n      vertex 1 0 0", "outer loop\n      vertex 1 0 0\n vertex 5 5 5"),
                        FileLocation::line(14), "facet with more than 3 vertices"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "      vertex 0 1 0\n    endloop\n  endfacet\nendsolid", "    endloop\n  endfacet\nendsolid"),
                        FileLocation::line(13), "facet with 2 vertices"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "facet normal 0 0 1\n    outer", "facet 0 0 1\n    outer"), FileLocation::line(2),
                        "expected 'normal', got '0'"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "outer loop", "outer lop"), FileLocation::line(3), "expected 'loop', got 'lop'"));
  EXPECT_TRUE(stl_error(kAsciiTwo + "junk\n", FileLocation::line(17), "expected 'solid', got 'junk'"));
  EXPECT_TRUE(stl_error("solid empty\nendsolid empty\n", FileLocation::none(), "no triangles"));
  EXPECT_TRUE(stl_error("solid x\n  vertex 1 2 3\n", FileLocation::line(2), "expected 'facet' or 'endsolid', got 'vertex'"));
}

TEST(StlReaderErrors, AsciiTruncated) {
  const std::string cut = kAsciiTwo.substr(0, kAsciiTwo.find("      vertex 1 1 0"));  // ends after line 11
  EXPECT_TRUE(stl_error(cut, FileLocation::line(12), "file ends where 'vertex' or 'endloop' was expected"));
  const std::string no_end = kAsciiTwo.substr(0, kAsciiTwo.find("endsolid two"));
  EXPECT_TRUE(stl_error(no_end, FileLocation::line(16), "file ends where 'facet' or 'endsolid' was expected"));
  EXPECT_TRUE(stl_error("solid", FileLocation::line(1), "file ends where 'facet' or 'endsolid'"));
}

TEST(StlReaderErrors, AsciiBadNumbers) {
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "vertex 1 1 0", "vertex 1 nan 0"), FileLocation::line(12), "'nan' is not finite"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "vertex 1 1 0", "vertex 1 1 inf"), FileLocation::line(12), "'inf' is not finite"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "vertex 1 1 0", "vertex 1 1 1e999"), FileLocation::line(12), "out of range"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "vertex 1 1 0", "vertex 1 1"), FileLocation::line(13), "'vertex' is not a number"));
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "normal 0 0 1", "normal 0 zero 1"), FileLocation::line(2), "'zero' is not a number"));
}

TEST(StlReaderErrors, AsciiWithBinaryGarbage) {
  EXPECT_TRUE(stl_error(replace(kAsciiTwo, "vertex 1 1 0", std::string("vertex 1 \0\x01 0", 13)), FileLocation::line(12),
                        "'\\x00\\x01' is not a number (the file starts with 'solid' but holds binary data"));
}

}  // namespace
}  // namespace trocar
