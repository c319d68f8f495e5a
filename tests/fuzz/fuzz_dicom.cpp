// The DICOM pixel-data length check (core/io/dicom_pixel_check.cpp), our own byte scanner
// run before ITK reads a file.
#include "fuzz_common.h"
#include "io/dicom_pixel_check.h"

MPUMESH_FUZZ_TARGET(mpumesh::check_dicom_pixel_data(bytes, "fuzz.dcm"))
