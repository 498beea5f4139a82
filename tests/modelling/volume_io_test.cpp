// Volume files and label selection: round trips through NIfTI, NRRD and MetaImage keep
// geometry and values; every kind of bad input is a FileError naming the file and the reason.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <Eigen/Geometry>

#include "trocar/core/error.h"
#include "trocar/modelling/label_select.h"
#include "trocar/modelling/organ_builder.h"
#include "trocar/modelling/phantoms.h"
#include "trocar/modelling/volume.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;

fs::path temp(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("trocar_modelling_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

/// Expects read_volume (or what `f` does) to throw a FileError naming `file` and saying `why`.
template <typename F>
void expect_file_error(F&& f, const fs::path& file, const std::string& why) {
  try {
    f();
    ADD_FAILURE() << "no error for " << file;
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
  }
}

Volume small_labelled() {
  Volume v = rasterise({12, 10, 8}, 2e-3, Vec3(0.01, -0.02, 0.03), [](const Vec3& x) {
    return (x - Vec3(0.021, -0.011, 0.037)).norm() < 0.006 ? 7 : 0;
  });
  v.direction = Eigen::AngleAxis<Real>(0.4, Vec3(0, 0, 1)).toRotationMatrix() * Vec3(-1, -1, 1).asDiagonal();
  v.spacing = Vec3(2e-3, 2.5e-3, 3e-3);
  return v;
}

class RoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(RoundTrip, KeepsGeometryAndValues) {
  const Volume v = small_labelled();
  const fs::path file = temp(std::string("round") + GetParam());
  write_volume(v, file);
  const Volume back = read_volume(file);
  EXPECT_EQ(back.dims, v.dims);
  EXPECT_LT((back.spacing - v.spacing).norm(), 1e-9);
  EXPECT_LT((back.origin - v.origin).norm(), 1e-6);   // float headers: µm
  EXPECT_LT((back.direction - v.direction).norm(), 1e-5);
  ASSERT_EQ(back.layers.size(), 1u);
  EXPECT_EQ(back.layers[0], v.layers[0]);
  EXPECT_EQ(label_counts(back).at(7), label_counts(v).at(7));
}

INSTANTIATE_TEST_SUITE_P(Formats, RoundTrip, ::testing::Values(".nii.gz", ".nii", ".nrrd", ".mha"));

TEST(VolumeErrors, MissingFile) {
  const fs::path file = temp("absent.nii.gz");
  expect_file_error([&] { read_volume(file); }, file, "no such file");
}

TEST(VolumeErrors, UnknownFormat) {
  const fs::path file = temp("notes.txt");
  write_bytes(file, "this is not an image\n");
  expect_file_error([&] { read_volume(file); }, file, "unknown volume format");
}

TEST(VolumeErrors, TruncatedAndCorruptGzip) {
  const fs::path good = temp("good.nii.gz");
  write_volume(sphere_phantom(1e-3, 0.01).volume, good);
  const std::string bytes = read_bytes(good);
  const fs::path truncated = temp("truncated.nii.gz");
  write_bytes(truncated, bytes.substr(0, bytes.size() / 2));
  expect_file_error([&] { read_volume(truncated); }, truncated, "truncated gzip stream");
  std::string flipped = bytes;
  for (std::size_t i = bytes.size() / 3; i < bytes.size() / 3 + 64; ++i) flipped[i] = static_cast<char>(flipped[i] ^ 0x5A);
  const fs::path corrupt = temp("corrupt.nii.gz");
  write_bytes(corrupt, flipped);
  expect_file_error([&] { read_volume(corrupt); }, corrupt, "corrupt gzip stream");
}

/// Cut short after the header: the voxels are missing, in every format.
class Truncated : public ::testing::TestWithParam<const char*> {};

TEST_P(Truncated, MissingVoxelsAreAnError) {
  const fs::path good = temp(std::string("whole") + GetParam());
  write_volume(ellipsoid_phantom(1e-3).volume, good);
  const std::string bytes = read_bytes(good);
  const fs::path cut = temp(std::string("cut") + GetParam());
  write_bytes(cut, bytes.substr(0, bytes.size() * 2 / 3));
  expect_file_error([&] { read_volume(cut); }, cut, "");
}

INSTANTIATE_TEST_SUITE_P(Formats, Truncated, ::testing::Values(".nii", ".nrrd", ".mha"));

/// A hand-written NIfTI-1 header: 4 × 4 × 4 uint8, pixdim 0 along y, no qform/sform.
TEST(VolumeErrors, ZeroSpacing) {
  std::string header(352, '\0');
  const auto put_i16 = [&](std::size_t at, std::int16_t v) { std::memcpy(&header[at], &v, 2); };
  const auto put_i32 = [&](std::size_t at, std::int32_t v) { std::memcpy(&header[at], &v, 4); };
  const auto put_f32 = [&](std::size_t at, float v) { std::memcpy(&header[at], &v, 4); };
  put_i32(0, 348);
  const std::int16_t dim[8] = {3, 4, 4, 4, 1, 1, 1, 1};
  for (int i = 0; i < 8; ++i) put_i16(40 + 2 * static_cast<std::size_t>(i), dim[i]);
  put_i16(70, 2);   // datatype uint8
  put_i16(72, 8);   // bitpix
  const float pixdim[8] = {1, 1, 0, 1, 0, 0, 0, 0};
  for (int i = 0; i < 8; ++i) put_f32(76 + 4 * static_cast<std::size_t>(i), pixdim[i]);
  put_f32(108, 352);  // vox_offset
  put_f32(112, 1);    // scl_slope
  header.replace(344, 4, "n+1\0", 4);
  const fs::path file = temp("zero_spacing.nii");
  write_bytes(file, header + std::string(64, '\1'));
  expect_file_error([&] { read_volume(file); }, file, "spacing");
}

TEST(LabelErrors, AbsentLabelListsThosePresent) {
  const Volume v = small_labelled();
  LabelQuery q;
  q.label = "42";
  try {
    select_mask(v, q);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("label 42 is not in the volume (labels present: 7)"), std::string::npos) << e.what();
  }
}

TEST(LabelErrors, UnknownNameListsTheNames) {
  Volume v = small_labelled();
  v.names[{0, 7}] = "spleen";
  LabelQuery q;
  q.label = "liver";
  try {
    select_mask(v, q);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("no segment is named \"liver\" (names: spleen)"), std::string::npos) << e.what();
  }
  q.label = "SPLEEN";  // names match case-insensitively
  EXPECT_EQ(select_mask(v, q).label, 7);
}

TEST(LabelErrors, EmptyAndOneVoxelLabelsAreTooSmall) {
  Volume v = make_volume({10, 10, 10}, Vec3::Constant(1e-3), Vec3::Zero());
  v.source = "one_voxel.nii.gz";
  v.layers[0][v.index(4, 4, 4)] = 3;
  OrganBuildOptions o;
  o.query.label = "3";
  try {
    build_organ(v, o);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("too small to mesh: 1 voxel(s)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("one_voxel.nii.gz"), std::string::npos);
  }
  o.query.label.clear();
  o.query.threshold_low = 10;
  try {
    build_organ(v, o);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("no voxel has a value in"), std::string::npos) << e.what();
  }
}

TEST(ClassMap, JsonTextAndPythonDictForms) {
  const fs::path json = temp("map.json");
  write_bytes(json, R"({"1": "spleen", "5": "liver"})");
  EXPECT_EQ(read_class_map(json).at(5), "liver");
  const fs::path text = temp("map.txt");
  write_bytes(text, "# TotalSegmentator\n1 spleen\n2: kidney_right\n  5: \"liver\",\r\n{\n");
  const auto map = read_class_map(text);
  EXPECT_EQ(map.size(), 3u);
  EXPECT_EQ(map.at(2), "kidney_right");
  EXPECT_EQ(map.at(5), "liver");
  const fs::path bad = temp("bad_map.txt");
  write_bytes(bad, "1 spleen\nliver five\n");
  expect_file_error([&] { read_class_map(bad); }, bad, ":2:");
}

TEST(ClassMap, SelectsByNameWhenTheFileNamesNothing) {
  const Volume v = small_labelled();
  LabelQuery q;
  q.label = "gallbladder";
  q.class_map = {{7, "gallbladder"}};
  const Mask m = select_mask(v, q);
  EXPECT_EQ(m.label, 7);
  EXPECT_EQ(m.count, label_counts(v).at(7));
  EXPECT_EQ(m.what, "label 7 (gallbladder)");
}

TEST(Threshold, SelectsTheGreyRange) {
  Volume v = make_volume({4, 4, 4}, Vec3::Constant(1e-3), Vec3::Zero());
  for (std::size_t p = 0; p < v.voxel_count(); ++p) v.layers[0][p] = static_cast<float>(p);
  LabelQuery q;
  q.threshold_low = 10;
  q.threshold_high = 19.5;
  EXPECT_EQ(select_mask(v, q).count, 10u);
  q.threshold_high.reset();
  EXPECT_EQ(select_mask(v, q).count, 54u);
}

}  // namespace
}  // namespace trocar
