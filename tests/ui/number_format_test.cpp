// Under a desktop number format with decimal commas, the studio's number
// fields show and take a decimal point, as its tables, legends and files do.
#include "lom/ui/number_format.hpp"

#include <gtest/gtest.h>

#include <QDoubleSpinBox>
#include <QLocale>
#include <QTest>

namespace lom::ui {
namespace {

TEST(NumberFormat, FieldsShowAndTakeADecimalPointUnderAGermanDesktop) {
  const QLocale before;
  QLocale::setDefault(QLocale(QLocale::German, QLocale::Germany));
  useCNumberFormat();
  QDoubleSpinBox field;
  field.setDecimals(3);
  field.setRange(0.0, 1.0);
  field.setValue(0.01);
  EXPECT_EQ(field.text(), "0.010");
  field.selectAll();
  QTest::keyClicks(&field, "0.02");
  field.interpretText();
  EXPECT_DOUBLE_EQ(field.value(), 0.02);
  QLocale::setDefault(before);
}

}  // namespace
}  // namespace lom::ui
