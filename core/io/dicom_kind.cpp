#include "io/dicom_kind.h"

#include <array>
#include <cstdint>
#include <utility>

#include "common/error.h"

namespace mpumesh {
namespace {

// The value of the first element (group, element) of string VR that parses, in explicit
// VR little or big endian or implicit VR little endian, trailing padding dropped.
std::string find_string(const std::string& b, uint16_t group, uint16_t element) {
  const std::string le{char(group & 0xff), char(group >> 8), char(element & 0xff), char(element >> 8)};
  const std::string be{char(group >> 8), char(group & 0xff), char(element >> 8), char(element & 0xff)};
  for (const bool big : {false, true}) {
    const std::string& tag = big ? be : le;
    for (size_t at = b.find(tag); at != std::string::npos && at + 8 <= b.size(); at = b.find(tag, at + 1)) {
      const auto* p = reinterpret_cast<const unsigned char*>(b.data() + at + 4);
      size_t start = 0, len = 0;
      if (p[0] >= 'A' && p[0] <= 'Z' && p[1] >= 'A' && p[1] <= 'Z') {  // explicit VR, 2-byte length
        start = at + 8;
        len = big ? (size_t(p[2]) << 8 | p[3]) : (size_t(p[3]) << 8 | p[2]);
      } else if (!big) {  // implicit VR, 4-byte length
        start = at + 8;
        len = size_t(p[0]) | size_t(p[1]) << 8 | size_t(p[2]) << 16 | size_t(p[3]) << 24;
      } else {
        continue;
      }
      if (len > 64 || start + len > b.size()) continue;
      std::string v = b.substr(start, len);
      while (!v.empty() && (v.back() == ' ' || v.back() == '\0')) v.pop_back();
      bool printable = true;
      for (char c : v) printable = printable && c >= 32 && c < 127;
      if (printable) return v;
    }
  }
  return "";
}

bool has_pixel_data(const std::string& b) {
  return b.find(std::string("\xe0\x7f\x10\x00", 4)) != std::string::npos ||
         b.find(std::string("\x7f\xe0\x00\x10", 4)) != std::string::npos;
}

// The storage classes that hold no image (PS3.4 Annex B), and the modalities of such.
std::string class_without_image(const std::string& uid, const std::string& modality) {
  static const std::array<std::pair<const char*, const char*>, 16> kClasses = {{
      {"1.2.840.10008.5.1.4.1.1.481.5", "an RT plan"},
      {"1.2.840.10008.5.1.4.1.1.481.8", "an RT ion plan"},
      {"1.2.840.10008.5.1.4.1.1.481.3", "an RT structure set"},
      {"1.2.840.10008.5.1.4.1.1.481.4", "an RT treatment record"},
      {"1.2.840.10008.5.1.4.1.1.481.6", "an RT treatment record"},
      {"1.2.840.10008.5.1.4.1.1.481.7", "an RT treatment summary record"},
      {"1.2.840.10008.5.1.4.1.1.88.", "a structured report"},
      {"1.2.840.10008.5.1.4.1.1.9.", "a waveform"},
      {"1.2.840.10008.5.1.4.1.1.11.", "a presentation state"},
      {"1.2.840.10008.5.1.4.1.1.104.", "an encapsulated document"},
      {"1.2.840.10008.5.1.4.1.1.66.1", "a spatial registration"},
      {"1.2.840.10008.5.1.4.1.1.66.3", "a deformable registration"},
      {"1.2.840.10008.5.1.4.1.1.66", "raw data"},
      {"1.2.840.10008.5.1.4.1.1.67", "a real world value mapping"},
      {"1.2.840.10008.1.3.10", "a DICOMDIR (a media directory)"},
      {"1.2.840.10008.5.1.4.34.", "an RT second-generation object"},
  }};
  // An entry ending in '.' is a family of classes; the others are one class each.
  for (const auto& [entry, what] : kClasses) {
    const std::string e = entry;
    if (e.back() == '.' ? uid.rfind(e, 0) == 0 : uid == e) return what;
  }
  static const std::array<std::pair<const char*, const char*>, 10> kModalities = {{
      {"RTPLAN", "an RT plan"},
      {"RTSTRUCT", "an RT structure set"},
      {"RTRECORD", "an RT treatment record"},
      {"SR", "a structured report"},
      {"ECG", "a waveform (ECG)"},
      {"HD", "a waveform (hemodynamic)"},
      {"PR", "a presentation state"},
      {"KO", "a key object selection"},
      {"DOC", "an encapsulated document"},
      {"REG", "a registration"},
  }};
  for (const auto& [m, what] : kModalities)
    if (modality == m) return what;
  return "";
}

}  // namespace

DicomKind dicom_kind(const std::string& b) {
  DicomKind k;
  k.sop_class = find_string(b, 0x0002, 0x0002);
  if (k.sop_class.empty()) k.sop_class = find_string(b, 0x0008, 0x0016);
  k.modality = find_string(b, 0x0008, 0x0060);
  k.pixel_data = has_pixel_data(b);
  k.no_image = class_without_image(k.sop_class, k.modality);
  return k;
}

namespace {

[[noreturn]] void refuse(const DicomKind& k, const std::string& name) {
  std::string detail;
  if (!k.sop_class.empty()) detail += "SOP class " + k.sop_class;
  if (!k.modality.empty()) detail += std::string(detail.empty() ? "" : ", ") + "modality " + k.modality;
  throw InputError(name + ": holds no image to mesh: " +
                   (k.no_image.empty() ? std::string("it has no pixel data") : "it is " + k.no_image) +
                   (detail.empty() ? "" : " (" + detail + ")"));
}

}  // namespace

void refuse_dicom_without_image(const std::string& bytes, const std::string& name) {
  const DicomKind k = dicom_kind(bytes);
  if (!k.no_image.empty()) refuse(k, name);
}

void explain_unreadable_dicom(const std::string& bytes, const std::string& name) {
  const DicomKind k = dicom_kind(bytes);
  const bool deflated = find_string(bytes, 0x0002, 0x0010) == "1.2.840.10008.1.2.1.99";
  if (!k.no_image.empty() || (!k.pixel_data && !deflated)) refuse(k, name);
}

}  // namespace mpumesh
