// Built with -fno-sanitize=pointer-overflow under UBSan (CMakeLists.txt): ITK 5.2's
// ConstNeighborhoodIterator offsets a null pointer in its boundary setup
// (itkConstNeighborhoodIterator.hxx:705), harmless and not ours.
#include "trocar/modelling/mask_components.h"

#include <itkBinaryBallStructuringElement.h>
#include <itkBinaryMorphologicalClosingImageFilter.h>
#include <itkConnectedComponentImageFilter.h>
#include <itkImage.h>
#include <itkImportImageFilter.h>
#include <itkRelabelComponentImageFilter.h>

namespace trocar {

namespace {

itk::ImportImageFilter<std::uint8_t, 3>::Pointer import_mask(const std::vector<std::uint8_t>& mask,
                                                             const std::array<std::size_t, 3>& dims) {
  using Import = itk::ImportImageFilter<std::uint8_t, 3>;
  auto import = Import::New();
  Import::SizeType size;
  for (unsigned a = 0; a < 3; ++a) size[a] = dims[a];
  import->SetRegion(Import::RegionType(size));
  import->SetImportPointer(const_cast<std::uint8_t*>(mask.data()), mask.size(), false);
  return import;
}

}  // namespace

std::vector<std::uint8_t> close_mask(const std::vector<std::uint8_t>& mask, const std::array<std::size_t, 3>& dims,
                                     const std::array<unsigned, 3>& radius) {
  using MaskImage = itk::Image<std::uint8_t, 3>;
  using Ball = itk::BinaryBallStructuringElement<std::uint8_t, 3>;
  Ball ball;
  Ball::SizeType r;
  for (unsigned a = 0; a < 3; ++a) r[a] = radius[a];
  ball.SetRadius(r);
  ball.CreateStructuringElement();
  auto import = import_mask(mask, dims);
  auto closing = itk::BinaryMorphologicalClosingImageFilter<MaskImage, MaskImage, Ball>::New();
  closing->SetInput(import->GetOutput());
  closing->SetKernel(ball);
  closing->SetForegroundValue(1);
  closing->SafeBorderOn();
  closing->Update();
  const std::uint8_t* out = closing->GetOutput()->GetBufferPointer();
  return {out, out + mask.size()};
}

Components connected_components(const std::vector<std::uint8_t>& mask, const std::array<std::size_t, 3>& dims) {
  using MaskImage = itk::Image<std::uint8_t, 3>;
  using LabelImage = itk::Image<std::uint32_t, 3>;
  auto import = import_mask(mask, dims);
  auto components = itk::ConnectedComponentImageFilter<MaskImage, LabelImage>::New();
  components->SetInput(import->GetOutput());
  components->FullyConnectedOff();  // 6-connected
  auto relabel = itk::RelabelComponentImageFilter<LabelImage, LabelImage>::New();
  relabel->SetInput(components->GetOutput());
  relabel->Update();
  Components out;
  for (const auto n : relabel->GetSizeOfObjectsInPixels()) out.sizes.push_back(static_cast<std::size_t>(n));
  const std::uint32_t* labels = relabel->GetOutput()->GetBufferPointer();
  out.labels.assign(labels, labels + mask.size());
  return out;
}

}  // namespace trocar
