// read_vtk: ASCII and BINARY, classic and 5.1 cell layouts, strips, skipped sections, and every
// malformed-input error with its line (ASCII) or byte offset (BINARY).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

/// How write_vtk lays out its file.
struct VtkLayout {
  bool binary = false;
  bool v51 = false;                ///< OFFSETS/CONNECTIVITY instead of count-prefixed cells
  bool doubles = false;            ///< POINTS as double instead of float
  const char* cells = "POLYGONS";  ///< or TRIANGLE_STRIPS, LINES, VERTICES
  std::string before_dataset;      ///< inserted before DATASET (e.g. a FIELD)
  std::string after_points;        ///< inserted after the point data
  std::string tail;                ///< appended at the end
};

/// Appends `value` big-endian (legacy VTK binary byte order).
template <class T>
void put_be(std::string& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

/// A legacy VTK POLYDATA file: test-only writer, so the reader can be checked on BINARY files.
std::string write_vtk(const std::vector<Vec3>& points, const std::vector<std::vector<int>>& cells,
                      const VtkLayout& o = {}) {
  std::string s = std::string("# vtk DataFile Version ") + (o.v51 ? "5.1" : "3.0") + "\ntest mesh\n" +
                  (o.binary ? "BINARY" : "ASCII") + "\n" + o.before_dataset + "DATASET POLYDATA\nPOINTS " +
                  std::to_string(points.size()) + (o.doubles ? " double\n" : " float\n");
  for (const Vec3& p : points) {
    for (int k = 0; k < 3; ++k) {
      if (!o.binary) s += std::to_string(p[k]) + (k == 2 ? "\n" : " ");
      else if (o.doubles) put_be(s, p[k]);
      else put_be(s, static_cast<float>(p[k]));
    }
  }
  if (o.binary) s += "\n";
  s += o.after_points;
  std::size_t total = 0;
  for (const auto& c : cells) total += c.size();
  auto put_int = [&](std::int64_t v, bool wide) {
    if (!o.binary) s += std::to_string(v) + " ";
    else if (wide) put_be(s, v);
    else put_be(s, static_cast<std::int32_t>(v));
  };
  if (o.v51) {
    s += std::string(o.cells) + " " + std::to_string(cells.size() + 1) + " " + std::to_string(total) +
         "\nOFFSETS vtktypeint64\n";
    std::int64_t offset = 0;
    put_int(0, true);
    for (const auto& c : cells) put_int(offset += static_cast<std::int64_t>(c.size()), true);
    s += "\nCONNECTIVITY vtktypeint64\n";
    for (const auto& c : cells)
      for (int i : c) put_int(i, true);
    s += "\n";
  } else {
    s += std::string(o.cells) + " " + std::to_string(cells.size()) + " " + std::to_string(total + cells.size()) + "\n";
    for (const auto& c : cells) {
      put_int(static_cast<std::int64_t>(c.size()), false);
      for (int i : c) put_int(i, false);
      if (!o.binary) s += "\n";
    }
    if (o.binary) s += "\n";
  }
  return s + o.tail;
}

TriMesh vtk(const std::string& s) { return read_vtk(s, "m.vtk"); }

/// Passes when reading `text` throws FileError naming m.vtk, exactly `where`, and `reason`.
::testing::AssertionResult vtk_error(const std::string& text, FileLocation where, const std::string& reason) {
  return test::throws_file_error([&] { (void)read_vtk(text, "m.vtk"); }, "m.vtk", where, reason);
}

FileLocation line(std::uint64_t l) { return FileLocation::line(l); }
FileLocation byte(std::uint64_t b) { return FileLocation::byte(b); }

const std::vector<Vec3> kPoints = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
const std::vector<std::vector<int>> kCells = {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}};

TEST(VtkReader, AsciiBinaryClassicAnd51AgreeExactly) {
  for (bool binary : {false, true}) {
    for (bool v51 : {false, true}) {
      for (bool doubles : {false, true}) {
        VtkLayout o;
        o.binary = binary;
        o.v51 = v51;
        o.doubles = doubles;
        const TriMesh m = vtk(write_vtk(kPoints, kCells, o));
        ASSERT_EQ(m.vertex_count(), 5u);
        ASSERT_EQ(m.triangle_count(), 4u);
        EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
        EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
        EXPECT_EQ(m.triangles[2], (Triangle{0, 1, 4}));
        EXPECT_EQ(m.positions[4], Vec3(0.5, 0.5, 1));
        EXPECT_TRUE(m.indices_valid());
      }
    }
  }
}

TEST(VtkReader, DoublePointsAreExactInBinary) {
  VtkLayout o;
  o.binary = true;
  o.doubles = true;
  const std::vector<Vec3> p = {{0.1, 1e-300, -7.25}, {1, 2, 3}, {4, 5, 6}};
  EXPECT_EQ(vtk(write_vtk(p, {{0, 1, 2}}, o)).positions[0], p[0]);
}

TEST(VtkReader, TriangleStripsAlternateWinding) {
  for (bool binary : {false, true}) {
    VtkLayout o;
    o.binary = binary;
    o.cells = "TRIANGLE_STRIPS";
    const TriMesh m = vtk(write_vtk(kPoints, {{0, 1, 2, 3, 4}}, o));
    ASSERT_EQ(m.triangle_count(), 3u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Triangle{2, 1, 3}));
    EXPECT_EQ(m.triangles[2], (Triangle{2, 3, 4}));
  }
}

TEST(VtkReader, SkipsFieldsMetadataVerticesLinesAndAttributes) {
  for (bool binary : {false, true}) {
    for (bool v51 : {false, true}) {
      VtkLayout o;
      o.binary = binary;
      o.v51 = v51;
      std::string field = "FIELD FieldData 2\ntimes 1 2 double\n";
      if (binary) {
        put_be(field, 1.5);
        put_be(field, 2.5);
        field += "\n";
      } else {
        field += "1.5 2.5\n";
      }
      field += "METADATA\nINFORMATION 0\n\nempty 1 0 int\n";
      if (binary) field += "\n";
      o.before_dataset = field;
      o.after_points = "METADATA\nINFORMATION 1\nNAME L2_NORM_RANGE LOCATION vtkDataArray\nDATA 2 0 1\n\n";
      VtkLayout lines = o;
      lines.cells = "LINES";
      std::string line_cells = write_vtk({}, {{0, 1}, {1, 2, 3}}, lines);
      line_cells = line_cells.substr(line_cells.find("LINES"));
      VtkLayout verts = o;
      verts.cells = "VERTICES";
      std::string vert_cells = write_vtk({}, {{4}}, verts);
      vert_cells = vert_cells.substr(vert_cells.find("VERTICES"));
      o.after_points += line_cells + vert_cells;
      o.tail = "POINT_DATA 5\nSCALARS s float 1\nLOOKUP_TABLE default\nthis is not parsed { [ \x01\x02";
      const TriMesh m = vtk(write_vtk(kPoints, kCells, o));
      EXPECT_EQ(m.triangle_count(), 4u) << binary << v51;
      EXPECT_EQ(m.vertex_count(), 5u);
    }
  }
}

TEST(VtkReader, KeywordsAreCaseInsensitiveAndCrlfIsFine) {
  const TriMesh m = vtk("# vtk DataFile Version 2.0\r\nhello\r\nascii\r\ndataset polydata\r\n"
                        "points 3 FLOAT\r\n0 0 0 1 0 0\r\n0 1 0\r\npolygons 1 4\r\n3 0 1 2\r\n");
  EXPECT_EQ(m.triangle_count(), 1u);
}

// --- errors -----------------------------------------------------------------------------------

TEST(VtkReaderErrors, Header) {
  EXPECT_TRUE(vtk_error("", line(1), "not a legacy VTK file"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0", line(2), "missing title"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nXML\n", line(3), "ASCII or BINARY"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n", line(4), "only DATASET POLYDATA"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\n\nPOINTS 0 float\n", line(5), "expected DATASET"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 0 float\nCOLORS 3\n", line(6),
                        "unknown or unsupported keyword 'COLORS'"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 bit\n", line(5), "unknown POINTS data type"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n1 2 3\n", FileLocation::none(),
                        "no POLYGONS or TRIANGLE_STRIPS"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOLYGONS 0 0\n", line(5), "before POINTS"));
  // Cell sections present but no triangle in them (a fuzz finding: the 5.1 layout with 0 cells).
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 5.1\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                        "LINES 1 3\n2 0 1\nPOLYGONS 0 0\n",
                        FileLocation::none(), "no triangles"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                        "POLYGONS 1 3\n2 0 1\n",
                        FileLocation::none(), "no triangles"));
  EXPECT_TRUE(vtk_error("# vtk DataFile Version 3.0\nt\nASCII\n", FileLocation::none(), "no DATASET"));
}

TEST(VtkReaderErrors, LyingCountsAreCaughtBeforeAllocating) {
  std::string a = write_vtk(kPoints, kCells);
  a.replace(a.find("POINTS 5"), 8, "POINTS 4000000000");
  EXPECT_TRUE(vtk_error(a, line(5), "POINTS count 4000000000 exceeds"));
  VtkLayout o;
  o.binary = true;
  std::string b = write_vtk(kPoints, kCells, o);
  b.replace(b.find("POINTS 5"), 8, "POINTS 60");
  const std::size_t data = b.find("float\n") + 6;
  EXPECT_TRUE(vtk_error(b, byte(data), "POINTS count 60 exceeds"));
  std::string c = write_vtk(kPoints, kCells, o);
  c.replace(c.find("POLYGONS 3 13"), 13, "POLYGONS 3 99999999999");
  EXPECT_TRUE(vtk_error(c, byte(c.find("POLYGONS") + 23), "cell array size count 99999999999 exceeds"));
}

TEST(VtkReaderErrors, IndexOutOfRange) {
  std::vector<std::vector<int>> bad = kCells;
  bad[2][1] = 5;
  EXPECT_TRUE(vtk_error(write_vtk(kPoints, bad), line(14), "point index 5 out of range (5 points)"));
  VtkLayout o;
  o.binary = true;
  const std::string b = write_vtk(kPoints, bad, o);
  const std::size_t cells = b.find("POLYGONS 3 13\n") + 14;
  EXPECT_TRUE(vtk_error(b, byte(cells + 4 * (5 + 4 + 2)), "point index 5 out of range"));
  o.v51 = true;
  bad[2][1] = -2;
  const std::string c = write_vtk(kPoints, bad, o);
  const std::size_t conn = c.find("CONNECTIVITY vtktypeint64\n") + 26;
  EXPECT_TRUE(vtk_error(c, byte(conn + 8 * (4 + 3 + 1)), "point index -2 out of range"));
}

TEST(VtkReaderErrors, CellArraysMustAddUp) {
  const std::string head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n";
  EXPECT_TRUE(vtk_error(head + "POLYGONS 1 4\n4 0 1 2 0\n", line(8), "overrun"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 1 5\n3 0 1 2 0\n", line(8), "do not fill"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 1 4\n-3 0 1 2\n", line(8), "negative cell size"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 2 1\n3\n", line(7), "cell count exceeds"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 2 3\nOFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2\n", line(9),
                        "OFFSETS must start at 0"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 2 3\nOFFSETS vtktypeint64\n1 3\nCONNECTIVITY vtktypeint64\n0 1 2\n", line(9),
                        "OFFSETS must start at 0"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 2 4\nOFFSETS vtktypeint64\n0 3\n", line(9), "differs from the connectivity size"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 2 3\nOFFSETS vtktypeint64\n0 3\nCONNECT vtktypeint64\n", line(10), "expected CONNECTIVITY"));
  EXPECT_TRUE(vtk_error(head + "POLYGONS 2 3\nOFFSETS float\n", line(8), "bad OFFSETS data type"));
}

TEST(VtkReaderErrors, NumbersAndNaN) {
  std::string a = write_vtk(kPoints, kCells);
  a.replace(a.find("0.500000 0.500000"), 8, "nan");
  EXPECT_TRUE(vtk_error(a, line(10), "not a finite number"));
  std::string w = write_vtk(kPoints, kCells);
  w.replace(w.find("0.500000 0.500000"), 8, "x");
  EXPECT_TRUE(vtk_error(w, line(10), "bad number 'x'"));
  std::vector<Vec3> p = kPoints;
  p[3].z() = std::numeric_limits<double>::infinity();
  VtkLayout o;
  o.binary = true;
  const std::string b = write_vtk(p, kCells, o);
  EXPECT_TRUE(vtk_error(b, byte(b.find("float\n") + 6 + 3 * 12 + 8), "not a finite number"));
}

TEST(VtkReaderErrors, TruncatedBinary) {
  VtkLayout o;
  o.binary = true;
  const std::string b = write_vtk(kPoints, kCells, o);
  const std::size_t cells = b.find("POLYGONS 3 13\n") + 14;
  EXPECT_TRUE(vtk_error(b.substr(0, cells + 10), byte(cells), "cell array size count 13 exceeds"));
  o.v51 = true;
  const std::string c = write_vtk(kPoints, kCells, o);
  const std::size_t conn = c.find("CONNECTIVITY vtktypeint64\n") + 26;
  EXPECT_TRUE(vtk_error(c.substr(0, conn + 20), byte(conn), "CONNECTIVITY count 10 exceeds"));
  o.v51 = false;
  EXPECT_TRUE(vtk_error(b.substr(0, cells - 1), byte(cells - 1), "expected a newline before binary data"));
  // Every prefix of every layout is rejected cleanly (the full file reads).
  for (bool binary : {false, true}) {
    for (bool v51 : {false, true}) {
      o.binary = binary;
      o.v51 = v51;
      const std::string s = write_vtk(kPoints, kCells, o);
      EXPECT_NO_THROW((void)vtk(s));
      const std::size_t end = s.find_last_not_of(" \n") + 1;  // trailing whitespace is optional
      for (std::size_t n = 0; n < end; ++n) EXPECT_THROW((void)vtk(s.substr(0, n)), FileError) << n;
    }
  }
}

}  // namespace
}  // namespace trocar
