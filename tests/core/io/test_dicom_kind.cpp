// What a DICOM file is (core/io/dicom_kind.h), on pydicom's test files: the kinds that
// hold no image named, an image's class not.
#include <gtest/gtest.h>

#include "common/error.h"
#include "io/dicom_kind.h"
#include "io/read_file.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(DicomKind, NamesTheKindsThatHoldNoImage) {
  MPUMESH_DATA_OR_SKIP(ct, test::pydicom_file("CT_small.dcm"), "python3-pydicom");
  const DicomKind image = dicom_kind(read_file(ct));
  EXPECT_EQ(image.sop_class, "1.2.840.10008.5.1.4.1.1.2");
  EXPECT_EQ(image.modality, "CT");
  EXPECT_TRUE(image.pixel_data);
  EXPECT_EQ(image.no_image, "");
  EXPECT_NO_THROW(refuse_dicom_without_image(read_file(ct), ct));
  for (const auto& [name, kind] : {std::pair<const char*, const char*>{"rtplan.dcm", "an RT plan"},
                                   {"rtstruct.dcm", "an RT structure set"},
                                   {"test-SR.dcm", "a structured report"},
                                   {"waveform_ecg.dcm", "a waveform"},
                                   {"ExplVR_BigEndNoMeta.dcm", "an RT ion plan"}}) {
    const std::string path = test::pydicom_file(name);
    ASSERT_FALSE(path.empty()) << name;
    const std::string bytes = read_file(path);
    EXPECT_EQ(dicom_kind(bytes).no_image, kind) << name;
    try {
      refuse_dicom_without_image(bytes, path);
      ADD_FAILURE() << name << " was not refused";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": holds no image to mesh: it is " + kind), std::string::npos)
          << e.what();
    }
  }
  // A segmentation holds its image as frames of 1-bit pixels.
  EXPECT_EQ(dicom_kind(read_file(test::pydicom_file("liver_1frame.dcm"))).no_image, "");
}

}  // namespace
}  // namespace mpumesh
