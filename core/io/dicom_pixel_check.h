// Truncated DICOM pixel data: GDCM (and so ITK) only warns "Incomplete Pixel Data found"
// and hands back a buffer padded with garbage. This check reads the Pixel Data element's
// header (7FE0,0010) from the file itself and refuses a file that holds fewer bytes than
// the element declares. Encapsulated (compressed) pixel data, whose length is undefined,
// is left to the decoder.
#pragma once

#include <string>

namespace mpumesh {

// Throws InputError naming `name` when the pixel data is cut short.
void check_dicom_pixel_data(const std::string& bytes, const std::string& name);
void check_dicom_pixel_data_file(const std::string& path);

}  // namespace mpumesh
