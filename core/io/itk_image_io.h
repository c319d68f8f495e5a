// The ITK side of volume I/O, behind a header free of Eigen (ITK bundles its own Eigen,
// which must not meet the system one in a translation unit). Direction is row-major:
// direction[3 * row + col], columns are the physical directions of the index axes.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mpumesh {

struct PlainVolume {
  std::array<int64_t, 3> dims{0, 0, 0};
  std::array<double, 3> spacing{1, 1, 1}, origin{0, 0, 0};
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<float> voxels;
  // Instead of `voxels`, where the file's own voxels are 16-bit integers and its format
  // applies no rescale (MetaImage, NRRD): read as they are stored, half the memory of
  // floats, and left in the reader's own buffer, which `voxels16_owner` keeps (a copy of
  // a full-resolution scan's 170 MB costs a fault per page). Empty otherwise.
  std::span<const int16_t> voxels16;
  std::shared_ptr<const void> voxels16_owner;
  std::string modality;
  std::vector<std::string> notes;  // what the libraries said while reading, harmless
};

// Both readers collect what ITK and GDCM say (io/library_messages.h): damage is an
// InputError, the rest are notes. Files are checked first (io/volume_integrity.h).
// A directory holding one DICOM series: slices sorted along the slice normal, rescale
// applied, irregular or duplicate slice positions refused.
PlainVolume itk_read_dicom_series(const std::string& dir);
// .dcm, .nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd.
PlainVolume itk_read_file(const std::string& path);
// .nii, .nii.gz, .nrrd, .mha (int16 when every voxel is an integer in range, else float),
// written atomically.
void itk_write_file(const PlainVolume& vol, const std::string& path);
void itk_write_dicom_series(const PlainVolume& vol, const std::string& dir);

}  // namespace mpumesh
