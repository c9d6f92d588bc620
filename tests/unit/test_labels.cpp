// The label set type and the built-in APC 2016 labels.
#include <set>
#include <stdexcept>

#include "lom/labels.hpp"
#include "test_support.hpp"

namespace {

TEST(LabelsTest, VocPaletteMatchesPascalVoc) {
  EXPECT_EQ(lom::vocColor(0), (lom::Rgb{0, 0, 0}));
  EXPECT_EQ(lom::vocColor(1), (lom::Rgb{128, 0, 0}));
  EXPECT_EQ(lom::vocColor(2), (lom::Rgb{0, 128, 0}));
  EXPECT_EQ(lom::vocColor(3), (lom::Rgb{128, 128, 0}));
  EXPECT_EQ(lom::vocColor(8), (lom::Rgb{64, 0, 0}));
  EXPECT_EQ(lom::vocColor(15), (lom::Rgb{192, 128, 128}));
}

TEST(LabelsTest, Apc2016HasFortyLabelsWithBackgroundFirst) {
  const lom::LabelSet labels = lom::apc2016Labels();
  ASSERT_EQ(labels.size(), 40);
  EXPECT_EQ(labels.at(0).name, "__background__");
  EXPECT_EQ(labels.at(19).name, "i_am_a_bunny_book");
  EXPECT_EQ(labels.at(39).name, "woods_extension_cord");
  std::set<std::string> names;
  for (const auto& label : labels.all()) {
    EXPECT_EQ(label.color, lom::vocColor(label.id));
    names.insert(label.name);
  }
  EXPECT_EQ(names.size(), 40u);
}

TEST(LabelsTest, LookupByIdAndName) {
  const lom::LabelSet labels = lom::apc2016Labels();
  EXPECT_TRUE(labels.contains(39));
  EXPECT_FALSE(labels.contains(40));
  EXPECT_FALSE(labels.contains(-1));
  EXPECT_THROW((void)labels.at(40), std::out_of_range);
  EXPECT_EQ(labels.findByName("rawlings_baseball"), 29);
  EXPECT_FALSE(labels.findByName("not_an_object").has_value());
}

TEST(LabelsTest, LabelSetRequiresIdsInOrder) {
  EXPECT_THROW(lom::LabelSet({{0, "a", {}}, {2, "b", {}}}), std::invalid_argument);
  const lom::LabelSet two({{0, "a", {}}, {1, "b", {1, 2, 3}}});
  EXPECT_EQ(two.size(), 2);
  EXPECT_FALSE(two == lom::LabelSet({{0, "a", {}}, {1, "b", {1, 2, 4}}}));
  EXPECT_TRUE(two == lom::LabelSet({{0, "a", {}}, {1, "b", {1, 2, 3}}}));
}

}  // namespace
