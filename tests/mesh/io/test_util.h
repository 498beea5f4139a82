#pragma once
/// Helpers shared by the mesh I/O tests: checking FileError messages, building binary STL bytes.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/mesh/io/mesh_io.h"
#include "support/shared_data.h"

namespace trocar::test {

/// Passes when `call()` throws FileError for `file`, at `where`, with a reason containing
/// `reason_part`, and what() holds the file name and the location ("file:12:" / "byte 80").
template <class Call>
::testing::AssertionResult throws_file_error(Call call, const std::string& file, FileLocation where,
                                             std::string_view reason_part) {
  try {
    call();
  } catch (const FileError& e) {
    const std::string what = e.what();
    std::string location;
    if (where.kind == FileLocation::Kind::kLine) location = file + ":" + std::to_string(where.value) + ": ";
    if (where.kind == FileLocation::Kind::kByte) location = file + ": byte " + std::to_string(where.value) + ": ";
    if (where.kind == FileLocation::Kind::kNone) location = file + ": ";
    if (e.file() != file || e.where().kind != where.kind || e.where().value != where.value ||
        what.find(location) != 0 || e.reason().find(reason_part) == std::string::npos) {
      return ::testing::AssertionFailure()
             << "wrong FileError: \"" << what << "\"; expected it to start with \"" << location
             << "\" and contain \"" << reason_part << "\"";
    }
    return ::testing::AssertionSuccess() << what;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw another exception: " << e.what();
  } catch (...) {
    return ::testing::AssertionFailure() << "threw a non-std exception";
  }
  return ::testing::AssertionFailure() << "did not throw";
}

/// One STL facet: three corners (float32, as the format stores them).
using Facet = std::array<std::array<float, 3>, 3>;

/// Appends v little-endian.
inline void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
}

/// Appends f's bits little-endian.
inline void put_f32(std::string& out, float f) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, 4);
  put_u32(out, bits);
}

/// Binary STL bytes: the 80-byte `header` (padded with spaces), the count (`count_override`
/// when ≥ 0, else the number of facets), zero normals, and `attribute` in every facet.
inline std::string make_binary_stl(const std::vector<Facet>& facets, std::string header = "test",
                                   std::int64_t count_override = -1, std::uint16_t attribute = 0) {
  header.resize(80, ' ');
  std::string out = header;
  put_u32(out, count_override >= 0 ? static_cast<std::uint32_t>(count_override)
                                   : static_cast<std::uint32_t>(facets.size()));
  for (const Facet& f : facets) {
    for (int k = 0; k < 3; ++k) put_f32(out, 0.0f);
    for (const auto& corner : f)
      for (float c : corner) put_f32(out, c);
    out += static_cast<char>(attribute & 0xFF);
    out += static_cast<char>(attribute >> 8);
  }
  return out;
}

/// Path of a file in the shared test meshes folder (check test::shared_meshes_dir() first: the
/// folder is absent in a user's clone).
inline std::string shared_mesh(const std::string& file) {
  return (std::filesystem::path(TROCAR_SHARED_MESHES_DEFAULT) / file).string();
}

}  // namespace trocar::test
