// Volume files through ITK: ImageIOFactory picks the reader by content and extension; every
// reader gives spacing, origin and direction in ITK's LPS physical space (NIfTI's RAS sform is
// converted by ITK). What ITK does not give, we read beside it: the segment names of a Slicer
// .seg.nrrd (its MetaDataDictionary carries the Segment<N>_* keys) and the label table a NIfTI
// header extension may hold (TotalSegmentator writes a Caret XML <LabelTable> there).
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <regex>
#include <string>
#include <system_error>

#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOFactory.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIOFactory.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>
#include <itkVectorImage.h>

#include "trocar/core/error.h"
#include "trocar/modelling/volume.h"
#include "trocar/modelling/volume_checks.h"

namespace trocar {
namespace {

constexpr Real kMm = 1e-3;

/// ITK finds readers through factories, which a program not built with ITK's own CMake
/// registration must register itself: exactly the three formats trocar reads.
void register_readers() {
  static const bool done = [] {
    itk::NiftiImageIOFactory::RegisterOneFactory();
    itk::NrrdImageIOFactory::RegisterOneFactory();
    itk::MetaImageIOFactory::RegisterOneFactory();
    itk::Object::SetGlobalWarningDisplay(false);
    return true;
  }();
  (void)done;
}

[[noreturn]] void fail(const std::string& file, const std::string& reason) {
  throw FileError(file, FileLocation::none(), reason);
}

bool ends_with(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  return s.size() >= n && std::equal(s.end() - static_cast<std::ptrdiff_t>(n), s.end(), suffix, suffix + n,
                                     [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

/// Names from a NIfTI-1 header extension holding a <LabelTable> of <Label Key="N">name</Label>
/// (Caret/GIFTI style, as TotalSegmentator writes). Reads only the header and extensions.
void read_nifti_label_table(const std::string& file, Volume& v) {
  gzFile f = gzopen(file.c_str(), "rb");
  if (f == nullptr) return;
  std::string head(352, '\0');
  const int got = gzread(f, head.data(), 352);
  std::int32_t sizeof_hdr = 0;
  float vox_offset = 0;
  if (got == 352) {
    std::memcpy(&sizeof_hdr, head.data(), 4);
    std::memcpy(&vox_offset, head.data() + 108, 4);
  }
  // Little-endian NIfTI-1 with the extension flag set and a sane offset (ITK has read the file
  // already, so anything else simply has no names for us).
  if (sizeof_hdr != 348 || head[348] == 0 || !(vox_offset > 352 && vox_offset < (1 << 26))) {
    gzclose(f);
    return;
  }
  std::string ext(static_cast<std::size_t>(vox_offset) - 352, '\0');
  const int n = gzread(f, ext.data(), static_cast<unsigned>(ext.size()));
  gzclose(f);
  if (n <= 0) return;
  ext.resize(static_cast<std::size_t>(n));
  const std::size_t table = ext.find("<LabelTable>");
  if (table == std::string::npos) return;
  static const std::regex label(R"re(<Label\s[^>]*Key\s*=\s*"(-?\d+)"[^>]*>\s*(?:<!\[CDATA\[)?([^<\]]*)(?:\]\]>)?\s*</Label>)re");
  const std::string body = ext.substr(table);
  for (auto it = std::sregex_iterator(body.begin(), body.end(), label); it != std::sregex_iterator(); ++it) {
    const int key = std::stoi((*it)[1].str());
    if (key != 0) v.names[{0, key}] = (*it)[2].str();
  }
}

/// Slicer segment metadata: Segment<N>_Name, _LabelValue, _Layer (layer 0 when absent).
void read_slicer_segments(const itk::MetaDataDictionary& dict, Volume& v) {
  for (int s = 0; s < 1000; ++s) {
    const std::string prefix = "Segment" + std::to_string(s) + "_";
    std::string name, value, layer = "0";
    if (!itk::ExposeMetaData<std::string>(dict, prefix + "Name", name)) {
      if (s > 0) break;
      continue;
    }
    if (!itk::ExposeMetaData<std::string>(dict, prefix + "LabelValue", value)) value = std::to_string(s + 1);
    itk::ExposeMetaData<std::string>(dict, prefix + "Layer", layer);
    try {
      v.names[{std::stoi(layer), std::stoi(value)}] = name;
    } catch (const std::exception&) {
      // A malformed value names nothing; the segment can still be selected by number.
    }
  }
}

}  // namespace

Volume read_volume(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(file, "no such file");
  register_readers();
  const bool nifti = ends_with(file, ".nii") || ends_with(file, ".nii.gz");
  if (nifti) check_nifti_file(file);
  if (ends_with(file, ".mha") || ends_with(file, ".mhd")) check_metaimage_file(file);
  itk::ImageIOBase::Pointer io = itk::ImageIOFactory::CreateImageIO(file.c_str(), itk::IOFileModeEnum::ReadMode);
  if (!io) {
    fail(file, "unknown volume format (trocar reads NIfTI .nii/.nii.gz, NRRD .nrrd/.nhdr/.seg.nrrd and "
               "MetaImage .mha/.mhd)");
  }
  using Image = itk::VectorImage<float, 3>;
  Image::Pointer image;
  try {
    io->SetFileName(file);
    io->ReadImageInformation();
    if (io->GetNumberOfDimensions() != 3) {
      fail(file, "a " + std::to_string(io->GetNumberOfDimensions()) + "-D image: trocar meshes 3-D volumes");
    }
    auto reader = itk::ImageFileReader<Image>::New();
    reader->SetImageIO(io);
    reader->SetFileName(file);
    reader->Update();
    image = reader->GetOutput();
  } catch (const itk::ExceptionObject& e) {
    std::string why = e.GetDescription();
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    fail(file, "cannot read the volume (corrupt, truncated or unsupported): " + why);
  }

  Volume v;
  v.source = file;
  const auto size = image->GetLargestPossibleRegion().GetSize();
  for (int a = 0; a < 3; ++a) {
    v.dims[static_cast<std::size_t>(a)] = size[static_cast<unsigned>(a)];
    v.spacing[a] = image->GetSpacing()[static_cast<unsigned>(a)] * kMm;
    v.origin[a] = image->GetOrigin()[static_cast<unsigned>(a)] * kMm;
    for (int b = 0; b < 3; ++b) v.direction(a, b) = image->GetDirection()[static_cast<unsigned>(a)][static_cast<unsigned>(b)];
  }
  for (int a = 0; a < 3; ++a) {
    if (!(std::isfinite(v.spacing[a]) && v.spacing[a] > 0)) {
      fail(file, "spacing along axis " + std::to_string(a) + " is " + std::to_string(v.spacing[a] / kMm) +
                     " mm: a volume needs a positive voxel size");
    }
  }
  if (!v.origin.allFinite() || !v.direction.allFinite() || std::abs(std::abs(v.direction.determinant()) - 1) > 1e-3) {
    fail(file, "origin or direction is not finite, or the direction is not a rotation/reflection");
  }
  if (v.voxel_count() == 0) fail(file, "the volume has no voxels");
  const unsigned layers = image->GetNumberOfComponentsPerPixel();
  v.layers.assign(layers, std::vector<float>(v.voxel_count()));
  const float* data = image->GetBufferPointer();
  for (std::size_t p = 0; p < v.voxel_count(); ++p) {
    for (unsigned l = 0; l < layers; ++l) v.layers[l][p] = data[p * layers + l];
  }
  for (const std::vector<float>& layer : v.layers) {
    for (float x : layer) {
      if (!std::isfinite(x)) fail(file, "the volume holds non-finite values");
    }
  }
  read_slicer_segments(io->GetMetaDataDictionary(), v);
  if (nifti) read_nifti_label_table(file, v);
  return v;
}

namespace {

template <typename Pixel>
void write_as(const Volume& v, const std::string& file) {
  using Image = itk::Image<Pixel, 3>;
  auto image = Image::New();
  typename Image::SizeType size;
  typename Image::SpacingType spacing;
  typename Image::PointType origin;
  typename Image::DirectionType direction;
  for (unsigned a = 0; a < 3; ++a) {
    size[a] = v.dims[a];
    spacing[a] = v.spacing[static_cast<int>(a)] / kMm;
    origin[a] = v.origin[static_cast<int>(a)] / kMm;
    for (unsigned b = 0; b < 3; ++b) direction[a][b] = v.direction(static_cast<int>(a), static_cast<int>(b));
  }
  image->SetRegions(typename Image::RegionType(size));
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  image->Allocate();
  Pixel* out = image->GetBufferPointer();
  const std::vector<float>& layer = v.layers.at(0);
  for (std::size_t p = 0; p < layer.size(); ++p) out[p] = static_cast<Pixel>(layer[p]);
  auto writer = itk::ImageFileWriter<Image>::New();
  writer->SetFileName(file);
  writer->SetInput(image);
  writer->SetUseCompression(true);
  writer->Update();
}

}  // namespace

void write_volume(const Volume& volume, const std::filesystem::path& path) {
  const std::string file = path.string();
  if (volume.layers.empty() || volume.layers[0].size() != volume.voxel_count() || volume.voxel_count() == 0) {
    fail(file, "write_volume: the volume has no voxels or a layer of the wrong size");
  }
  bool bytes = true;
  for (float x : volume.layers[0]) bytes = bytes && x >= 0 && x <= 255 && x == std::floor(x);
  register_readers();
  try {
    if (bytes) {
      write_as<unsigned char>(volume, file);
    } else {
      write_as<float>(volume, file);
    }
  } catch (const itk::ExceptionObject& e) {
    fail(file, std::string("cannot write the volume: ") + e.GetDescription());
  }
}

}  // namespace trocar
