// Volume files. Reading dispatches on what the path is: a directory is a DICOM series
// (slices ordered by ImagePositionPatient along the slice normal, rescale slope and
// intercept applied, irregular spacing refused); .dcm a single DICOM file; .inv3 an
// InVesalius project; .nii, .nii.gz, .nrrd, .nhdr, .mha, .mhd through ITK. The volume
// keeps its physical geometry. Errors are InputError naming the path and the problem.
#pragma once

#include <string>

#include "volume/volume.h"

namespace mpumesh {

Volume read_volume(const std::string& path);

// InVesalius 3 project (.inv3: gzip'd tar of main.plist + matrix.dat), from memory.
Volume parse_inv3(const std::string& bytes, const std::string& name);

// The project's masks as one label map on the matrix's grid: a voxel holds 1 + the index
// of the first mask (by index) that holds it, 0 where none does. InVesalius's masks are
// thresholds of the image, often nested (bone inside a wider soft-tissue range): the
// bone stays bone and the wider mask keeps the rest.
Volume parse_inv3_masks(const std::string& bytes, const std::string& name);

// .nii, .nii.gz, .nrrd, .mha by extension, written atomically. Voxels are stored as
// float32 unless every value is an integer in int16 range (then int16, as CT is).
void write_volume(const Volume& vol, const std::string& path);

// A DICOM series (one CT image file per slice, int16 with rescale 1/0) into `dir`,
// which is created; for tests and for users whose tools want DICOM.
void write_dicom_series(const Volume& vol, const std::string& dir);

}  // namespace mpumesh
