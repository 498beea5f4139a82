// The extraction chain. Everything runs in voxel index space (the padded vtkImageData has
// origin −pad and unit spacing), and the finished points are mapped to world through the
// volume's origin, direction and spacing, so that any direction matrix (flipped axes of NIfTI
// sforms and NRRD space directions included) is honoured exactly. The winding is then set by
// the sign of the enclosed volume, which also undoes a mirroring direction.
#include "trocar/modelling/surface.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <itkConnectedComponentImageFilter.h>
#include <itkImage.h>
#include <itkImportImageFilter.h>
#include <itkRelabelComponentImageFilter.h>
#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkDecimatePro.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkFlyingEdges3D.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkImageGaussianSmooth.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataConnectivityFilter.h>
#include <vtkQuadricDecimation.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowedSincPolyDataFilter.h>

#include "trocar/core/error.h"
#include "trocar/mesh/validate.h"
#include "trocar/modelling/vtk_threads.h"

namespace trocar {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

[[noreturn]] void fail(const Volume& v, const std::string& reason) { throw FileError(v.source, FileLocation::none(), reason); }

/// Relabels the mask's 6-connected components by size (ITK), keeps the largest or those of at
/// least min_voxels; returns the kept mask.
std::vector<std::uint8_t> keep_components(const Volume& volume, const Mask& mask, const SurfaceOptions& options,
                                          Surface& out) {
  using MaskImage = itk::Image<std::uint8_t, 3>;
  using LabelImage = itk::Image<std::uint32_t, 3>;
  auto import = itk::ImportImageFilter<std::uint8_t, 3>::New();
  itk::ImportImageFilter<std::uint8_t, 3>::SizeType size;
  for (unsigned a = 0; a < 3; ++a) size[a] = volume.dims[a];
  import->SetRegion(itk::ImportImageFilter<std::uint8_t, 3>::RegionType(size));
  import->SetImportPointer(const_cast<std::uint8_t*>(mask.inside.data()), mask.inside.size(), false);
  auto components = itk::ConnectedComponentImageFilter<MaskImage, LabelImage>::New();
  components->SetInput(import->GetOutput());
  components->FullyConnectedOff();  // 6-connected: what the 0.5 iso-surface joins
  auto relabel = itk::RelabelComponentImageFilter<LabelImage, LabelImage>::New();
  relabel->SetInput(components->GetOutput());
  relabel->Update();
  const auto& sizes = relabel->GetSizeOfObjectsInPixels();
  out.components = sizes.size();
  std::uint32_t keep = 0;  // components 1..keep are kept (sorted by size, largest first)
  for (std::size_t c = 0; c < sizes.size(); ++c) {
    const bool wanted = options.largest_component_only ? c == 0 : sizes[c] >= options.min_component_voxels;
    if (wanted && sizes[c] >= options.min_component_voxels) keep = static_cast<std::uint32_t>(c + 1);
  }
  if (keep == 0) {
    fail(volume, mask.what + " is too small to mesh: " + std::to_string(sizes.empty() ? 0 : sizes[0]) +
                     " voxel(s) in its largest part, at least " + std::to_string(options.min_component_voxels) +
                     " needed");
  }
  out.components_kept = keep;
  std::vector<std::uint8_t> kept(mask.inside.size(), 0);
  const std::uint32_t* labels = relabel->GetOutput()->GetBufferPointer();
  for (std::size_t p = 0; p < kept.size(); ++p) {
    kept[p] = labels[p] != 0 && labels[p] <= keep ? 1 : 0;
    out.kept_voxels += kept[p];
  }
  return kept;
}

/// The kept mask in a vtkImageData padded by `pad` background voxels on every side (so a
/// label touching the volume's edge still closes), origin −pad, unit spacing (index space).
vtkSmartPointer<vtkImageData> padded_image(const Volume& volume, const std::vector<std::uint8_t>& kept, int pad) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  const int nx = static_cast<int>(volume.dims[0]) + 2 * pad;
  const int ny = static_cast<int>(volume.dims[1]) + 2 * pad;
  const int nz = static_cast<int>(volume.dims[2]) + 2 * pad;
  image->SetDimensions(nx, ny, nz);
  image->SetOrigin(-pad, -pad, -pad);
  image->SetSpacing(1, 1, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* out = static_cast<std::uint8_t*>(image->GetScalarPointer());
  std::fill(out, out + static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz), 0);
  for (std::size_t k = 0; k < volume.dims[2]; ++k) {
    for (std::size_t j = 0; j < volume.dims[1]; ++j) {
      const std::size_t row = (static_cast<std::size_t>(pad) + k) * static_cast<std::size_t>(ny) + static_cast<std::size_t>(pad) + j;
      std::copy_n(kept.data() + volume.index(0, j, k), volume.dims[0], out + row * static_cast<std::size_t>(nx) + static_cast<std::size_t>(pad));
    }
  }
  return image;
}

/// A VTK ProgressEvent observer forwarding to `progress` under `stage`.
struct ProgressBridge {
  const ProgressFn* fn;
  std::string stage;
  static void forward(vtkObject* caller, unsigned long, void* client, void*) {
    auto* self = static_cast<ProgressBridge*>(client);
    auto* algorithm = vtkAlgorithm::SafeDownCast(caller);
    if (self->fn != nullptr && *self->fn && algorithm != nullptr) (*self->fn)(self->stage, algorithm->GetProgress());
  }
};

void observe(vtkAlgorithm* algorithm, ProgressBridge& bridge, vtkCallbackCommand* command) {
  command->SetCallback(&ProgressBridge::forward);
  command->SetClientData(&bridge);
  algorithm->AddObserver(vtkCommand::ProgressEvent, command);
}

/// vtkPolyData (triangles, index space) → TriMesh in world, unused points dropped.
TriMesh to_world_mesh(vtkPolyData* poly, const Volume& volume) {
  TriMesh mesh;
  std::vector<std::int64_t> remap(static_cast<std::size_t>(poly->GetNumberOfPoints()), -1);
  vtkCellArray* polys = poly->GetPolys();
  vtkNew<vtkIdList> ids;
  for (polys->InitTraversal(); polys->GetNextCell(ids) != 0;) {
    if (ids->GetNumberOfIds() != 3) continue;
    Triangle t{};
    for (int c = 0; c < 3; ++c) {
      const auto id = static_cast<std::size_t>(ids->GetId(c));
      if (remap[id] < 0) {
        double p[3];
        poly->GetPoint(static_cast<vtkIdType>(id), p);
        remap[id] = static_cast<std::int64_t>(mesh.positions.size());
        mesh.positions.push_back(volume.index_to_world(Vec3(p[0], p[1], p[2])));
      }
      t[static_cast<std::size_t>(c)] = static_cast<std::uint32_t>(remap[id]);
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    mesh.triangles.push_back(t);
  }
  // Flying edges winds its triangles by the scalar gradient, which points inward for a mask;
  // the simulator wants outward normals (positive enclosed volume).
  if (mesh.signed_volume() < 0) {
    for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

/// The largest connected surface (decimation can leave a sliver apart), or all of it.
vtkSmartPointer<vtkPolyData> largest_region(vtkPolyData* surface, bool largest_only) {
  if (!largest_only) return surface;
  vtkNew<vtkPolyDataConnectivityFilter> connectivity;
  connectivity->SetInputData(surface);
  connectivity->SetExtractionModeToLargestRegion();
  connectivity->Update();
  return connectivity->GetOutput();
}

bool closed_manifold(vtkPolyData* surface, const Volume& volume) {
  const MeshReport r = validate(to_world_mesh(surface, volume));
  return r.closed && r.manifold && r.nonmanifold_vertices == 0;
}

}  // namespace

Surface extract_surface(const Volume& volume, const Mask& mask, const SurfaceOptions& options, const ProgressFn& progress) {
  use_one_vtk_thread();
  Surface out;
  auto t0 = Clock::now();
  if (progress) progress("components", 0);
  const std::vector<std::uint8_t> kept = keep_components(volume, mask, options, out);
  out.times.components = seconds_since(t0);

  // Extraction: flying edges on the binary mask (vertices at edge midpoints), or on the
  // Gaussian-smoothed mask at level 0.5 (vertices interpolated: sub-voxel, no staircase).
  t0 = Clock::now();
  ProgressBridge extract_bridge{&progress, "extract"};
  vtkNew<vtkCallbackCommand> extract_cmd;
  const Vec3 sigma_voxels = Vec3::Constant(options.presmooth_sigma).cwiseQuotient(volume.spacing);
  const int pad = 1 + static_cast<int>(std::ceil(3 * sigma_voxels.maxCoeff()));
  vtkSmartPointer<vtkImageData> image = padded_image(volume, kept, pad);
  vtkSmartPointer<vtkPolyData> surface;
  if (options.presmooth_sigma > 0) {
    vtkNew<vtkImageGaussianSmooth> gauss;
    gauss->SetInputData(image);
    gauss->SetStandardDeviations(sigma_voxels.x(), sigma_voxels.y(), sigma_voxels.z());
    gauss->SetRadiusFactors(3, 3, 3);
    gauss->SetDimensionality(3);
    vtkNew<vtkFlyingEdges3D> edges;
    edges->SetInputConnection(gauss->GetOutputPort());
    edges->SetValue(0, 0.5);
    edges->ComputeNormalsOff();
    edges->ComputeGradientsOff();
    edges->ComputeScalarsOff();
    observe(edges, extract_bridge, extract_cmd);
    edges->Update();
    surface = edges->GetOutput();
  } else {
    vtkNew<vtkDiscreteFlyingEdges3D> edges;
    edges->SetInputData(image);
    edges->SetValue(0, 1);
    edges->ComputeNormalsOff();
    edges->ComputeGradientsOff();
    edges->ComputeScalarsOff();
    observe(edges, extract_bridge, extract_cmd);
    edges->Update();
    surface = edges->GetOutput();
  }
  out.raw = to_world_mesh(surface, volume);
  out.times.extract = seconds_since(t0);
  if (out.raw.empty()) fail(volume, mask.what + ": the extracted surface is empty");

  // Smoothing without shrinking: Taubin's windowed-sinc low-pass filter (vtkWindowedSinc),
  // coordinates normalised to the unit cube so the pass band does not depend on the size.
  t0 = Clock::now();
  if (options.smooth_iterations > 0) {
    ProgressBridge bridge{&progress, "smooth"};
    vtkNew<vtkCallbackCommand> cmd;
    vtkNew<vtkWindowedSincPolyDataFilter> smooth;
    smooth->SetInputData(surface);
    smooth->SetNumberOfIterations(options.smooth_iterations);
    smooth->SetPassBand(options.smooth_passband);
    smooth->BoundarySmoothingOff();
    smooth->FeatureEdgeSmoothingOff();
    smooth->NonManifoldSmoothingOn();
    smooth->NormalizeCoordinatesOn();
    observe(smooth, bridge, cmd);
    smooth->Update();
    surface = smooth->GetOutput();
  }
  out.times.smooth = seconds_since(t0);

  // Decimation: Garland–Heckbert quadric edge collapse with volume preservation. It does not
  // check the link condition, so on some inputs it leaves a non-manifold edge or a pinhole; the
  // result is then made again by vtkDecimatePro with topology preserved, which never does.
  t0 = Clock::now();
  const auto raw_triangles = static_cast<double>(surface->GetNumberOfPolys());
  vtkSmartPointer<vtkPolyData> smoothed = surface;
  out.decimator = "none";
  if (options.target_triangles > 0 && raw_triangles > static_cast<double>(options.target_triangles)) {
    const double reduction = 1.0 - static_cast<double>(options.target_triangles) / raw_triangles;
    ProgressBridge bridge{&progress, "decimate"};
    vtkNew<vtkCallbackCommand> cmd;
    vtkNew<vtkQuadricDecimation> quadric;
    quadric->SetInputData(smoothed);
    quadric->SetTargetReduction(reduction);
    quadric->VolumePreservationOn();
    observe(quadric, bridge, cmd);
    quadric->Update();
    surface = largest_region(quadric->GetOutput(), options.largest_component_only);
    out.decimator = "quadric";
    if (!closed_manifold(surface, volume)) {
      vtkNew<vtkDecimatePro> pro;
      pro->SetInputData(smoothed);
      pro->SetTargetReduction(reduction);
      pro->PreserveTopologyOn();
      pro->SplittingOff();
      pro->BoundaryVertexDeletionOff();
      pro->SetMaximumError(VTK_DOUBLE_MAX);
      pro->SetFeatureAngle(60);
      observe(pro, bridge, cmd);
      pro->Update();
      surface = largest_region(pro->GetOutput(), options.largest_component_only);
      out.decimator = "pro (quadric left a non-manifold edge)";
    }
  } else {
    surface = largest_region(surface, options.largest_component_only);
  }
  out.times.decimate = seconds_since(t0);

  t0 = Clock::now();
  out.mesh = to_world_mesh(surface, volume);
  out.times.clean = seconds_since(t0);
  if (out.mesh.empty()) fail(volume, mask.what + ": the decimated surface is empty");
  if (progress) progress("done", 1);
  return out;
}

}  // namespace trocar
