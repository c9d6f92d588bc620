#include "lom/ui/number_format.hpp"

#include <QLocale>
#include <clocale>

namespace lom::ui {

void useCNumberFormat() {
  std::setlocale(LC_NUMERIC, "C");
  // Widgets made from now on (spin boxes) take the default locale's numbers.
  QLocale c = QLocale::c();
  c.setNumberOptions(QLocale::OmitGroupSeparator);
  QLocale::setDefault(c);
}

}  // namespace lom::ui
