// Label values (src/labels/label_values.h): --labels lists, the labels a slice holds in each
// sample type (negative, fractional and oversized values are no label), and their masks.
#include "labels/label_values.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace mvox {
namespace {

template <class T>
SliceView view_of(const std::vector<T>& samples, SampleType type, std::uint32_t width) {
  SliceView view;
  view.samples = samples.data();
  view.width = width;
  view.height = static_cast<std::uint32_t>(samples.size() / width);
  view.row_stride_bytes = width * sizeof(T);
  view.type = type;
  return view;
}

TEST(LabelValues, ListsAreWholeNumbersFromOneSortedWithoutRepeats) {
  LabelChoice choice;
  EXPECT_EQ(parse_label_choice("", &choice), "");
  EXPECT_TRUE(choice.all);
  EXPECT_EQ(parse_label_choice("7,1,4,1", &choice), "");
  EXPECT_FALSE(choice.all);
  EXPECT_EQ(choice.listed, (std::vector<std::uint32_t>{1, 4, 7}));
  EXPECT_TRUE(choice.wants(4));
  EXPECT_FALSE(choice.wants(5));
  for (const char* bad : {"0", "-1", "1.5", "x", "1,,2", "16777217", " 3", "3 "})
    EXPECT_NE(parse_label_choice(bad, &choice), "") << bad;
  EXPECT_EQ(parse_label_choice("16777216", &choice), "");
}

TEST(LabelValues, EachSampleTypeGivesItsPositiveWholeLabels) {
  const LabelChoice all;
  LabelSlices slices(all);
  EXPECT_EQ(slices.labels_in(view_of(std::vector<std::uint8_t>{0, 3, 3, 255, 1, 0}, SampleType::u8, 3)),
            (std::vector<std::uint32_t>{1, 3, 255}));
  EXPECT_EQ(slices.labels_in(
                view_of(std::vector<std::uint16_t>{0, 65535, 300, 300}, SampleType::u16, 2)),
            (std::vector<std::uint32_t>{300, 65535}));
  EXPECT_EQ(slices.labels_in(view_of(std::vector<std::int16_t>{-5, 0, 12, -32768}, SampleType::i16, 2)),
            (std::vector<std::uint32_t>{12}));
  EXPECT_EQ(slices.labels_in(view_of(std::vector<float>{0.0f, 2.0f, 2.5f, -3.0f, 16777216.0f,
                                                        33554432.0f, 9.0f, 2.0f},
                                     SampleType::f32, 4)),
            (std::vector<std::uint32_t>{2, 9, 16777216}));
  // A list keeps only its labels.
  LabelChoice listed;
  ASSERT_EQ(parse_label_choice("3", &listed), "");
  LabelSlices some(listed);
  EXPECT_EQ(some.labels_in(view_of(std::vector<std::uint8_t>{1, 3, 4, 3}, SampleType::u8, 2)),
            (std::vector<std::uint32_t>{3}));
}

TEST(LabelValues, MasksMarkExactlyEachLabelsVoxels) {
  const LabelChoice all;
  LabelSlices slices(all);
  const std::vector<std::uint16_t> samples = {5, 5, 0, 9, 9, 5, 0, 0, 9};
  const SliceView view = view_of(samples, SampleType::u16, 3);
  std::vector<std::uint8_t> five(9, 7), nine(9, 7), absent(9, 7);  // 7: must be overwritten
  slices.fill_masks(view, {5, 9, 11}, {five.data(), nine.data(), absent.data()});
  EXPECT_EQ(five, (std::vector<std::uint8_t>{1, 1, 0, 0, 0, 1, 0, 0, 0}));
  EXPECT_EQ(nine, (std::vector<std::uint8_t>{0, 0, 0, 1, 1, 0, 0, 0, 1}));
  EXPECT_EQ(absent, std::vector<std::uint8_t>(9, 0));
}

}  // namespace
}  // namespace mvox
