// Label maps: a label's indicator, the labels counted, the list of labels parsed.
#include <gtest/gtest.h>

#include "common/error.h"
#include "segment/label_map.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(LabelMap, TheIndicatorIsOneOnTheLabelZeroOnTheBackgroundMinusOneOnOtherLabels) {
  Volume v;
  v.dims = {12, 1, 1};
  v.voxels = {0, 3, 7, 3, 7, 7, 7, 7, 7, 7, 7, 0};
  v.source = "map.nii";
  const Volume ind = seg::label_indicator(v, 7);
  EXPECT_EQ(ind.voxels, (std::vector<float>{0, -1, 1, -1, 1, 1, 1, 1, 1, 1, 1, 0}));
  EXPECT_EQ(ind.source, "map.nii (label 7)");
  EXPECT_THROW(
      {
        try {
          seg::label_indicator(v, 5);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "map.nii (label 5): no voxel holds this label");
          throw;
        }
      },
      InputError);
  try {
    seg::label_indicator(v, 3);
    ADD_FAILURE() << "2 voxels are too few";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "map.nii (label 3): 2 voxels, too small to mesh (a label needs at least 8)");
  }
}

TEST(LabelMap, CountsTheLabelsAndRefusesWhatIsNoLabelMap) {
  Volume v;
  v.dims = {5, 1, 1};
  v.voxels = {0, 3, 7, 3, 0};
  v.source = "map.nii";
  EXPECT_EQ(seg::label_voxel_counts(v), (std::map<int64_t, int64_t>{{3, 2}, {7, 1}}));
  v.voxels[1] = 2.5f;
  EXPECT_THROW(seg::label_voxel_counts(v), InputError);
  v.dims = {int64_t(seg::kMaxLabels) + 1, 1, 1};
  v.voxels.resize(size_t(v.dims[0]));
  for (size_t i = 0; i < v.voxels.size(); ++i) v.voxels[i] = float(i + 1);
  EXPECT_THROW(seg::label_voxel_counts(v), InputError);
}

TEST(LabelMap, ParsesAllOrAListOfLabels) {
  EXPECT_TRUE(seg::parse_label_list("all").empty());
  EXPECT_EQ(seg::parse_label_list("3,7,12"), (std::vector<int64_t>{3, 7, 12}));
  for (const char* bad : {"", "0", "-2", "3,", "3,,4", "x", "3.5", "3,3"})
    EXPECT_THROW(seg::parse_label_list(bad), InputError) << bad;
}

}  // namespace
}  // namespace mpumesh
