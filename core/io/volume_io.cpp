#include "io/volume_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/error.h"
#include "common/text.h"
#include "io/isolated_read.h"
#include "io/itk_image_io.h"
#include "io/read_file.h"

namespace mpumesh {
namespace {

Volume from_plain(PlainVolume&& p, const std::string& source) {
  Volume v;
  v.source = source;
  v.dims = p.dims;
  for (int a = 0; a < 3; ++a) {
    v.spacing[a] = p.spacing[size_t(a)];
    v.origin[a] = p.origin[size_t(a)];
    for (int b = 0; b < 3; ++b) v.direction(a, b) = p.direction[size_t(3 * a + b)];
  }
  if (!p.voxels16.empty()) v.voxels.assign(p.voxels16.begin(), p.voxels16.end());
  else v.voxels = std::move(p.voxels);
  v.modality = std::move(p.modality);
  v.read_notes = std::move(p.notes);
  return v;
}

PlainVolume to_plain(const Volume& v) {
  PlainVolume p;
  p.dims = v.dims;
  for (int a = 0; a < 3; ++a) {
    p.spacing[size_t(a)] = v.spacing[a];
    p.origin[size_t(a)] = v.origin[a];
    for (int b = 0; b < 3; ++b) p.direction[size_t(3 * a + b)] = v.direction(a, b);
  }
  p.voxels = v.voxels;
  p.modality = v.modality;
  return p;
}

// How a message names the reader of a file, by its extension.
std::string reader_name(const std::string& path) {
  const std::string p = lower_case(path);
  if (p.ends_with(".dcm")) return "the DICOM reader";
  if (p.ends_with(".nii") || p.ends_with(".nii.gz")) return "the NIfTI reader";
  if (p.ends_with(".nrrd") || p.ends_with(".nhdr")) return "the NRRD reader";
  if (p.ends_with(".mha") || p.ends_with(".mhd")) return "the MetaImage reader";
  return "the volume reader";
}

}  // namespace

Volume read_volume(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path + ": file or directory not found");
  Volume v;
  // ITK, GDCM and their codecs run in a child process (io/isolated_read.h); the .inv3
  // reader is the project's own, and fuzzed.
  if (fs::is_directory(path, ec))
    v = from_plain(read_isolated(path, "the DICOM reader", [&] { return itk_read_dicom_series(path); }), path);
  else if (lower_case(path).ends_with(".inv3")) v = parse_inv3(read_file(path), path);
  else v = from_plain(read_isolated(path, reader_name(path), [&] { return itk_read_file(path); }), path);
  validate_volume(v, path);
  require_finite_voxels(v, path);
  return v;
}

void write_volume(const Volume& vol, const std::string& path) {
  validate_volume(vol, path);
  itk_write_file(to_plain(vol), path);
}

void write_dicom_series(const Volume& vol, const std::string& dir) {
  validate_volume(vol, dir);
  itk_write_dicom_series(to_plain(vol), dir);
}

}  // namespace mpumesh
