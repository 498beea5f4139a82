#include "trocar/modelling/volume_checks.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "trocar/core/error.h"

namespace trocar {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& reason) {
  throw FileError(file, FileLocation::none(), reason);
}

/// Decompresses (or, for a plain file, reads) the whole file through zlib's gz reader, which
/// checks a gzip stream's CRC and length; returns the first `keep` bytes and the total length.
std::uint64_t read_stream(const std::string& file, std::string& head, std::size_t keep) {
  gzFile f = gzopen(file.c_str(), "rb");
  if (f == nullptr) fail(file, "cannot open the file");
  std::uint64_t total = 0;
  char buffer[1 << 16];
  int n = 0;
  while ((n = gzread(f, buffer, sizeof buffer)) > 0) {
    if (head.size() < keep) head.append(buffer, std::min<std::size_t>(static_cast<std::size_t>(n), keep - head.size()));
    total += static_cast<std::uint64_t>(n);
  }
  int code = Z_OK;
  std::string why = n < 0 ? gzerror(f, &code) : "";
  if (why.rfind(file + ": ", 0) == 0) why.erase(0, file.size() + 2);
  const int close = gzclose(f);
  if (n < 0) fail(file, "corrupt gzip stream (" + why + ")");
  if (close == Z_BUF_ERROR) fail(file, "truncated gzip stream (unexpected end of file)");
  if (close != Z_OK) fail(file, "corrupt gzip stream");
  return total;
}

std::uint64_t inflated_length(const std::string& file, const std::string& compressed, bool& complete) {
  z_stream z{};
  if (inflateInit(&z) != Z_OK) fail(file, "zlib could not start");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
  z.avail_in = static_cast<uInt>(compressed.size());
  std::uint64_t total = 0;
  char buffer[1 << 16];
  int rc = Z_OK;
  while (rc == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof buffer;
    rc = inflate(&z, Z_NO_FLUSH);
    total += sizeof buffer - z.avail_out;
    if (rc == Z_BUF_ERROR && z.avail_in == 0) break;  // input ended before the stream did
  }
  inflateEnd(&z);
  if (rc != Z_STREAM_END && rc != Z_BUF_ERROR) fail(file, "corrupt zlib data (" + std::string(z.msg ? z.msg : "bad stream") + ")");
  complete = rc == Z_STREAM_END;
  return total;
}

std::size_t meta_element_size(const std::string& type) {
  static const std::map<std::string, std::size_t> sizes{
      {"MET_CHAR", 1},  {"MET_UCHAR", 1}, {"MET_SHORT", 2},     {"MET_USHORT", 2},     {"MET_INT", 4},
      {"MET_UINT", 4},  {"MET_LONG", 4},  {"MET_ULONG", 4},     {"MET_LONG_LONG", 8},  {"MET_ULONG_LONG", 8},
      {"MET_FLOAT", 4}, {"MET_DOUBLE", 8}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

}  // namespace

void check_nifti_file(const std::string& file) {
  std::string h;
  const std::uint64_t length = read_stream(file, h, 348);
  std::int32_t sizeof_hdr = 0;
  if (h.size() >= 4) std::memcpy(&sizeof_hdr, h.data(), 4);
  if (h.size() < 348 || sizeof_hdr != 348) return;  // NIfTI-2 or big-endian: ITK's word stands
  std::int16_t dim[8], bitpix = 0, sform_code = 0;
  float pixdim[8], srow[12], vox_offset = 0;
  std::memcpy(dim, h.data() + 40, sizeof dim);
  std::memcpy(&bitpix, h.data() + 72, 2);
  std::memcpy(pixdim, h.data() + 76, sizeof pixdim);
  std::memcpy(&vox_offset, h.data() + 108, 4);
  std::memcpy(&sform_code, h.data() + 254, 2);
  std::memcpy(srow, h.data() + 280, sizeof srow);
  std::uint64_t voxels = 1;
  for (int d = 1; d <= std::clamp<int>(dim[0], 1, 7); ++d) voxels *= static_cast<std::uint64_t>(std::max<std::int16_t>(dim[d], 1));
  const std::uint64_t need = static_cast<std::uint64_t>(std::max(vox_offset, 348.f)) + voxels * static_cast<std::uint64_t>(std::max<int>(bitpix, 8) / 8);
  if (length < need) {
    fail(file, "truncated: the header promises " + std::to_string(need) + " bytes, the file holds " + std::to_string(length));
  }
  for (int a = 0; a < 3; ++a) {
    const double size = sform_code > 0 ? std::sqrt(double(srow[a]) * srow[a] + double(srow[4 + a]) * srow[4 + a] +
                                                   double(srow[8 + a]) * srow[8 + a])
                                       : std::abs(double(pixdim[1 + a]));
    if (!(std::isfinite(size) && size > 0)) {
      fail(file, "voxel size along axis " + std::to_string(a) + " is " + std::to_string(size) + " (" +
                     (sform_code > 0 ? "sform column" : "pixdim") + "): a volume needs a positive spacing");
    }
  }
}

void check_metaimage_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open the file");
  std::map<std::string, std::string> keys;
  std::string line;
  std::streamoff data_start = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    key.erase(key.find_last_not_of(" \t") + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    keys[key] = value;
    if (key == "ElementDataFile") {
      data_start = in.tellg();
      break;
    }
  }
  const std::size_t element = meta_element_size(keys["ElementType"]);
  if (element == 0 || keys["DimSize"].empty() || keys["ElementDataFile"].empty()) return;  // ITK's word stands
  std::uint64_t need = element;
  std::istringstream dims(keys["DimSize"]);
  for (std::uint64_t d = 0; dims >> d;) need *= d;
  if (!keys["ElementNumberOfChannels"].empty()) need *= std::stoull(keys["ElementNumberOfChannels"]);
  std::string data;
  std::string data_file = keys["ElementDataFile"];
  if (data_file == "LOCAL") {
    in.seekg(data_start);
    data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    data_file = file;
  } else {
    if (data_file.find(' ') != std::string::npos || data_file == "LIST") return;  // file lists: ITK's word stands
    const std::filesystem::path path = std::filesystem::path(file).parent_path() / data_file;
    std::ifstream raw(path, std::ios::binary);
    if (!raw) fail(file, "its data file " + path.string() + " cannot be opened");
    data.assign(std::istreambuf_iterator<char>(raw), std::istreambuf_iterator<char>());
    data_file = path.string();
  }
  const bool compressed = keys["CompressedData"] == "True" || keys["CompressedData"] == "true";
  bool complete = true;
  const std::uint64_t have = compressed ? inflated_length(data_file, data, complete) : data.size();
  if (!complete || have < need) {
    fail(data_file, std::string(compressed ? "truncated compressed data" : "truncated data") + ": " +
                        std::to_string(need) + " bytes of voxels expected, " + std::to_string(have) + " found");
  }
}

}  // namespace trocar
