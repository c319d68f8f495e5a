// What a DICOM file is, read from its own bytes before any reader touches it: its SOP
// class (0002,0002 or 0008,0016), its modality (0008,0060) and whether it holds pixel
// data (7FE0,0010). A file of a class that holds no image (an RT plan, an RT structure
// set, a structured report, a waveform, a presentation state, ...) is refused with what
// it is, rather than with a reader's complaint about its header.
#pragma once

#include <string>

namespace mpumesh {

struct DicomKind {
  std::string sop_class;  // "" when absent
  std::string modality;   // "" when absent
  bool pixel_data = false;
  // "an RT plan", "a structured report", ...: what a file of a class that holds no image
  // is; "" for an image class, or when unknown.
  std::string no_image;
};

DicomKind dicom_kind(const std::string& bytes);

// Throws InputError naming `name` and what the file is when it is of a class that holds no
// image to mesh.
void refuse_dicom_without_image(const std::string& bytes, const std::string& name);
// For a file the reader refused: throws InputError saying it holds no image when it has
// no pixel data (a deflated data set, whose elements are compressed, is not judged);
// returns otherwise.
void explain_unreadable_dicom(const std::string& bytes, const std::string& name);

}  // namespace mpumesh
