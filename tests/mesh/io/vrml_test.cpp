// read_vrml: scene graph features, the liver .wrl against its .obj, Coin3D as an oracle,
// and every malformed-input error with its line.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"
#include "trocar/mesh/io/mesh_io.h"

#if TROCAR_HAVE_COIN
#include <Inventor/SbMatrix.h>
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/SoPrimitiveVertex.h>
#include <Inventor/actions/SoCallbackAction.h>
#include <Inventor/nodes/SoSeparator.h>
#endif

namespace trocar {
namespace {

const std::string kHead = "#VRML V2.0 utf8\n";

TriMesh wrl(const std::string& body) { return read_vrml(kHead + body, "s.wrl"); }

/// Passes when reading `text` (whole file) throws FileError naming s.wrl, the line (0: no
/// location), and `reason`.
::testing::AssertionResult wrl_error(const std::string& text, std::uint64_t line, const std::string& reason) {
  return test::throws_file_error([&] { (void)read_vrml(text, "s.wrl"); }, "s.wrl",
                                 line ? FileLocation::line(line) : FileLocation::none(), reason);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string face_set(const std::string& points, const std::string& index, const std::string& extra = "") {
  return "Shape { geometry IndexedFaceSet { " + extra + " coord Coordinate { point [ " + points +
         " ] } coordIndex [ " + index + " ] } }\n";
}

const std::string kTri = "0 0 0, 1 0 0, 0 1 0";

TEST(VrmlReader, SingleTriangle) {
  const TriMesh m = wrl(face_set(kTri, "0 1 2 -1"));
  ASSERT_EQ(m.vertex_count(), 3u);
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.positions[1], Vec3(1, 0, 0));
  EXPECT_TRUE(m.indices_valid());
}

TEST(VrmlReader, PolygonsAreFannedAndTrailingPolygonNeedsNoSeparator) {
  const TriMesh m = wrl(face_set("0 0 0, 1 0 0, 1 1 0, 0 1 0, 2 0 0", "0 1 2 3 -1 1 4 2 -1 -1 0 1 -1 0 4 2"));
  ASSERT_EQ(m.triangle_count(), 4u);  // quad → 2, triangle, degenerate pair dropped, trailing triangle
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (Triangle{1, 4, 2}));
  EXPECT_EQ(m.triangles[3], (Triangle{0, 4, 2}));
}

TEST(VrmlReader, CcwFalseFlipsWinding) {
  const TriMesh m = wrl(face_set(kTri, "0 1 2", "ccw FALSE"));
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 2, 1}));
}

TEST(VrmlReader, SyntaxNoise) {
  // Comments, commas anywhere, strings with braces and escapes, numbers in every form, other
  // IndexedFaceSet fields, unknown nodes, PROTO/EXTERNPROTO/ROUTE, single values without [].
  const std::string text = kHead +
      "# comment { [\n"
      "PROTO Thing [ field SFVec3f size 1 1 1 ] { Group { children [] } }\n"
      "EXTERNPROTO Ext [ field SFInt32 x ] [ \"urn:a\" \"b.wrl\" ]\n"
      "WorldInfo { title \"a } \\\" ] { string\" info [ \"x\", \"y\" ] }\n"
      "Thing { size 2 2 2 }\n"
      "DEF T Transform { children [\n"
      "  Shape {\n"
      "    appearance Appearance { material DEF M Material { diffuseColor 1 0 0 } }\n"
      "    geometry IndexedFaceSet {\n"
      "      solid FALSE convex TRUE creaseAngle 0.5 colorPerVertex TRUE\n"
      "      color Color { color [ 1 0 0, 0 1 0, 0 0 1 ] } colorIndex [ 0 1 2 -1 ]\n"
      "      normal Normal { vector [ 0 0 1, 0 0 1, 0 0 1 ] } normalIndex [ 0, 1, 2, -1 ]\n"
      "      texCoord TextureCoordinate { point [ 0 0, 1 0, 0 1 ] } texCoordIndex [ 0 1 2 -1 ]\n"
      "      coord Coordinate { point [ +1.5e0,-0,.5 , 2. 0x0 0 , 0 1E0 0 ] }\n"
      "      coordIndex [ 0, 1, 2, -1, ]\n"
      "      ROUTE A.b TO C.d\n"
      "    }\n"
      "  }\n"
      "  Shape { appearance Appearance { material USE M } geometry Box { size 1 1 1 } }\n"
      "] }\n"
      "DEF TS TimeSensor { loop TRUE }\n"
      "ROUTE TS.fraction_changed TO T.set_rotation\n";
  // "0x0" is not a float: hexadecimal is for integers only.
  EXPECT_TRUE(wrl_error(text, 15, "expected a number"));
  std::string fixed = text;
  fixed.replace(fixed.find("0x0"), 3, "0");
  const TriMesh m = read_vrml(fixed, "s.wrl");
  ASSERT_EQ(m.vertex_count(), 3u);
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.positions[0], Vec3(1.5, 0, 0.5));
  EXPECT_EQ(m.positions[1], Vec3(2, 0, 0));
}

TEST(VrmlReader, HexadecimalCoordIndexAndSingleValues) {
  const TriMesh m = wrl("Shape { geometry IndexedFaceSet { coord Coordinate { point 1 2 3 } coordIndex 0 } }\n" +
                        face_set(kTri, "0x0 0X1 0x2"));
  ASSERT_EQ(m.vertex_count(), 4u);
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{1, 2, 3}));
}

TEST(VrmlReader, TransformComposesAsTheSpecSays) {
  const TriMesh m = wrl(
      "Transform { translation 1 2 3 rotation 0 0 2 1.5707963267948966 scale 2 3 4\n"
      "  scaleOrientation 1 0 0 0.5 center 0.5 -1 2 children [" + face_set("1 2 3, 4 5 6, 7 8 9", "0 1 2") + "] }");
  ASSERT_EQ(m.vertex_count(), 3u);
  const Vec3 T(1, 2, 3), C(0.5, -1, 2), S(2, 3, 4);
  const Mat3 R = Eigen::AngleAxisd(1.5707963267948966, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 SR = Eigen::AngleAxisd(0.5, Vec3::UnitX()).toRotationMatrix();
  const Vec3 points[3] = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  for (int i = 0; i < 3; ++i) {
    const Vec3 expected = T + C + R * (SR * (S.asDiagonal() * (SR.transpose() * (points[i] - C))));
    EXPECT_NEAR((m.positions[i] - expected).norm(), 0.0, 1e-12) << i;
  }
}

TEST(VrmlReader, NestedTransformsMultiply) {
  const TriMesh m = wrl("Transform { translation 10 0 0 children Transform { scale 2 2 2 children [" +
                        face_set(kTri, "0 1 2") + "] } }");
  EXPECT_EQ(m.positions[1], Vec3(12, 0, 0));
  EXPECT_EQ(m.positions[2], Vec3(10, 2, 0));
}

TEST(VrmlReader, MirroringTransformKeepsTheOutsideOutside) {
  const TriMesh m = wrl("Transform { scale -1 1 1 children [" + face_set(kTri, "0 1 2") + "] }");
  EXPECT_EQ(m.triangles[0], (Triangle{0, 2, 1}));
}

TEST(VrmlReader, UseReinstantiatesUnderEachTransform) {
  const TriMesh m = wrl("Transform { translation 0 0 1 children [ DEF S " + face_set(kTri, "0 1 2") +
                        "] }\n Transform { translation 0 0 5 children [ USE S ] }\n USE S\n");
  ASSERT_EQ(m.vertex_count(), 9u);
  ASSERT_EQ(m.triangle_count(), 3u);
  EXPECT_EQ(m.positions[1], Vec3(1, 0, 1));
  EXPECT_EQ(m.positions[4], Vec3(1, 0, 5));
  EXPECT_EQ(m.positions[7], Vec3(1, 0, 0));
  EXPECT_EQ(m.triangles[2], (Triangle{6, 7, 8}));
  EXPECT_TRUE(m.indices_valid());
}

TEST(VrmlReader, UsedCoordinateAndRedefinedNames) {
  const TriMesh m = wrl("Shape { geometry IndexedFaceSet { coord DEF C Coordinate { point [ " + kTri +
                        " ] } coordIndex [ 0 1 2 ] } }\n"
                        "Shape { geometry IndexedFaceSet { coord USE C coordIndex [ 2 1 0 ] } }\n"
                        "DEF C Coordinate { point [ 5 5 5, 6 6 6, 7 7 7 ] }\n"
                        "Shape { geometry IndexedFaceSet { coord USE C coordIndex [ 0 1 2 ] } }\n");
  ASSERT_EQ(m.vertex_count(), 9u);
  EXPECT_EQ(m.triangles[1], (Triangle{5, 4, 3}));
  EXPECT_EQ(m.positions[3], Vec3(0, 0, 0));
  EXPECT_EQ(m.positions[6], Vec3(5, 5, 5));  // the later DEF wins for later USEs
}

TEST(VrmlReader, GroupingNodesAndSwitch) {
  const std::string s = face_set(kTri, "0 1 2");
  const TriMesh m = wrl("Group { children [ Anchor { url \"x\" children [" + s + "] }\n"
                        "Billboard { axisOfRotation 0 1 0 children [" + s + "] }\n"
                        "Collision { collide FALSE proxy Shape { geometry Box {} } children [" + s + "] } ] }\n"
                        "Switch { whichChoice 2 choice [ " + s + " NULL Transform { translation 0 0 7 children [" +
                        s + "] } ] }\n"
                        "Switch { choice [ " + s + " ] }\n"
                        "Switch { whichChoice 5 choice [ " + s + " ] }\n");
  ASSERT_EQ(m.triangle_count(), 4u);
  EXPECT_EQ(m.positions[9], Vec3(0, 0, 7));
}

TEST(VrmlReader, UseOfNodeDefinedInsideSkippedNodeAddsNothing) {
  const TriMesh m = wrl("Script { field SFNode n DEF Inner Group {} url \"javascript: x = {\" }\n"
                        "Group { children [ USE Inner " + face_set(kTri, "0 1 2") + "] }");
  EXPECT_EQ(m.triangle_count(), 1u);
}

TEST(VrmlReader, LiverMatchesTheObjBitForBit) {
  TROCAR_SHARED_MESH_OR_SKIP(wrl_path, "liver_sofa_smooth.wrl");
  TROCAR_SHARED_MESH_OR_SKIP(obj_path, "liver_sofa_smooth.obj");
  const TriMesh m = load_mesh(wrl_path);
  // A 10-line OBJ parser (v x y z; f a//n b//n c//n) keeps this test independent of read_obj.
  std::vector<Vec3> v;
  std::vector<Triangle> f;
  std::istringstream in(read_file(obj_path.string()));
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string key, a[3];
    ls >> key >> a[0] >> a[1] >> a[2];
    if (key == "v") {
      Vec3 p;
      for (int k = 0; k < 3; ++k) std::from_chars(a[k].data(), a[k].data() + a[k].size(), p[k]);
      v.push_back(p);
    } else if (key == "f") {
      Triangle t;
      for (int k = 0; k < 3; ++k) t[k] = static_cast<std::uint32_t>(std::stoul(a[k]) - 1);
      f.push_back(t);
    }
  }
  ASSERT_EQ(v.size(), 2194u);
  ASSERT_EQ(f.size(), 4384u);
  ASSERT_EQ(m.vertex_count(), v.size());
  ASSERT_EQ(m.triangles, f);
  for (std::size_t i = 0; i < v.size(); ++i) ASSERT_EQ(m.positions[i], v[i]) << i;  // exact doubles
}

// --- Coin3D oracle ----------------------------------------------------------------------------

using Corners = std::array<std::array<float, 3>, 3>;

std::vector<Corners> sorted_corners(const std::vector<Corners>& tris) {
  std::vector<Corners> out = tris;
  for (Corners& c : out) std::sort(c.begin(), c.end());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Corners> ours(const TriMesh& m) {
  std::vector<Corners> out;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    Corners c;
    const auto p = m.corners(t);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) c[i][k] = static_cast<float>(p[i][k]);
    out.push_back(c);
  }
  return sorted_corners(out);
}

#if TROCAR_HAVE_COIN
void coin_triangle(void* data, SoCallbackAction* action, const SoPrimitiveVertex* a, const SoPrimitiveVertex* b,
                   const SoPrimitiveVertex* c) {
  auto* out = static_cast<std::vector<Corners>*>(data);
  const SbMatrix& model = action->getModelMatrix();
  Corners t;
  const SoPrimitiveVertex* v[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    SbVec3f w;
    model.multVecMatrix(v[i]->getPoint(), w);
    for (int k = 0; k < 3; ++k) t[i][k] = w[k];
  }
  out->push_back(t);
}

std::vector<Corners> coin(const std::string& text) {
  SoDB::init();
  SoInput input;
  input.setBuffer(text.data(), text.size());
  SoSeparator* root = SoDB::readAll(&input);
  EXPECT_NE(root, nullptr);
  if (!root) return {};
  root->ref();
  std::vector<Corners> tris;
  SoCallbackAction action;
  action.addTriangleCallback(SoNode::getClassTypeId(), coin_triangle, &tris);
  action.apply(root);
  root->unref();
  return sorted_corners(tris);
}

void expect_same_as_coin(const std::string& text) {
  const std::vector<Corners> a = ours(read_vrml(text, "s.wrl"));
  const std::vector<Corners> b = coin(text);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t t = 0; t < a.size(); ++t)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(a[t][i][k], b[t][i][k], 2e-6 * std::max(1.0f, std::abs(a[t][i][k]))) << t;
}

TEST(VrmlReaderCoin, LiverAgreesWithCoin) {
  TROCAR_SHARED_MESH_OR_SKIP(path, "liver_sofa_smooth.wrl");
  expect_same_as_coin(read_file(path.string()));
}

TEST(VrmlReaderCoin, TransformsUseAndSwitchAgreeWithCoin) {
  const std::string s = face_set("0.1 0.2 0.3, 1.7 0.1 0.4, 0.2 1.9 0.8, 1.1 1.3 2.9", "0 1 2 -1 0 2 3 -1 1 3 2");
  expect_same_as_coin(kHead +
      "DEF A Transform { translation 1 2 3 rotation 0.3 0.4 0.5 0.7 scale 2 0.5 1.5 scaleOrientation 0 1 1 0.3"
      " center 0.2 -0.4 0.6 children [ DEF S " + s + " ] }\n"
      "Transform { translation -3 0 0 rotation 1 0 0 2 children [ USE A USE S ] }\n"
      "Group { children [ Switch { whichChoice 1 choice [ USE S Transform { scale 3 3 3 children [ USE S ] } ] } ] }\n"
      "Transform { scale -1 1 1 children [ Shape { geometry IndexedFaceSet { ccw FALSE coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 2 ] } } ] }\n");
}
#endif

// --- errors -----------------------------------------------------------------------------------

TEST(VrmlReaderErrors, MissingHeader) {
  EXPECT_TRUE(wrl_error("#VRML V1.0 ascii\nSeparator {}\n", 1, "#VRML V2.0 utf8"));
  EXPECT_TRUE(wrl_error("", 1, "header"));
}

TEST(VrmlReaderErrors, UnbalancedBraces) {
  EXPECT_TRUE(wrl_error(kHead + "Group {\n children [\n", 3, "never closed"));
  EXPECT_TRUE(wrl_error(kHead + "Group {\n children [ ]\n", 2, "end of file inside 'Group'"));
  EXPECT_TRUE(wrl_error(kHead + "WorldInfo {\n info [ }\n", 3, "mismatched '}'"));
  EXPECT_TRUE(wrl_error(kHead + "WorldInfo {\n\n", 2, "never closed"));
  EXPECT_TRUE(wrl_error(kHead + "\n}\n", 3, "unexpected '}'"));
  EXPECT_TRUE(wrl_error(kHead + "Group { children [ ] ] }\n", 2, "expected a field name"));
  EXPECT_TRUE(wrl_error(kHead + "PROTO P [ \n { }\n", 2, "never closed"));
}

TEST(VrmlReaderErrors, UnknownUseName) {
  EXPECT_TRUE(wrl_error(kHead + face_set(kTri, "0 1 2") + "\nGroup { children [\n USE Nowhere ] }", 5,
                        "USE of unknown name 'Nowhere'"));
}

TEST(VrmlReaderErrors, CoordIndexOutOfRange) {
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet {\ncoord Coordinate { point [ " + kTri +
                        " ] }\ncoordIndex [ 0 1 2 -1\n 0 1 3 ] } }", 5, "coordIndex 3 out of range (3 points)"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet {\ncoordIndex [ 0 1 -2 ]\ncoord Coordinate { point [ " +
                        kTri + " ] } } }", 3, "below -1"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet {\ncoordIndex [ 0 1 99999999999 ] } }", 3, "out of range"));
}

TEST(VrmlReaderErrors, BadNumbers) {
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet { coord Coordinate {\n point [ 0 0 0,\n 1 zero 0 ] } } }",
                        4, "expected a number, found 'zero'"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet { coord Coordinate {\n point [ 0 0 nan ] } } }", 3,
                        "not finite"));
  EXPECT_TRUE(wrl_error(kHead + "Transform {\n translation 1 inf 0 }", 3, "not finite"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet { coord Coordinate {\n point [ 0 0 0, 1 1 ] } } }", 3,
                        "multiple of 3"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet { coordIndex [\n 0 1.5 ] } }", 3, "expected an integer"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet { ccw\n maybe } }", 3, "TRUE or FALSE"));
  EXPECT_TRUE(wrl_error(kHead + "WorldInfo { title \"open\n\n", 2, "unterminated string"));
}

TEST(VrmlReaderErrors, StructureErrors) {
  EXPECT_TRUE(wrl_error(kHead + "Group\n [ ]", 3, "expected '{' after node type 'Group'"));
  EXPECT_TRUE(wrl_error(kHead + "Shape { geometry IndexedFaceSet {\n coord USE X } }", 3, "unknown name 'X'"));
  EXPECT_TRUE(wrl_error(kHead + "DEF G Group {}\nShape { geometry\n IndexedFaceSet { coord USE G } }", 4,
                        "coord must be a Coordinate"));
  EXPECT_TRUE(wrl_error(kHead + "ROUTE a.b\n FROM c.d", 3, "expected TO"));
  EXPECT_TRUE(wrl_error(kHead + "Group { children }", 2, "expected a node"));
  EXPECT_TRUE(wrl_error(kHead + "Group { children [ \"s\" ] }", 2, "expected a node"));
  EXPECT_TRUE(wrl_error(kHead + "WorldInfo {}\n", 0, "no IndexedFaceSet"));
}

TEST(VrmlReaderErrors, NestingDepthIsLimited) {
  std::string deep = kHead;
  for (int i = 0; i < 300; ++i) deep += "Group { children [\n";
  EXPECT_TRUE(wrl_error(deep, 258, "nested deeper than 256"));
  // Depth through USE: each level USEs the previous one.
  std::string chain = kHead + "DEF L0 " + face_set(kTri, "0 1 2");
  for (int i = 1; i < 300; ++i)
    chain += "DEF L" + std::to_string(i) + " Group { children [ USE L" + std::to_string(i - 1) + " ] }\n";
  EXPECT_TRUE(wrl_error(chain, 2, "deeper than 256 nodes through USE"));
}

TEST(VrmlReaderErrors, ExponentialUseIsBounded) {
  std::string bomb = kHead + "DEF L0 " + face_set(kTri, "0 1 2");
  for (int i = 1; i < 60; ++i)
    bomb += "DEF L" + std::to_string(i) + " Group { children [ USE L" + std::to_string(i - 1) + " USE L" +
            std::to_string(i - 1) + " ] }\n";
  try {
    (void)read_vrml(bomb, "s.wrl");
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("too much geometry"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trocar
