#include "lom/ui/number_format.hpp"

#include <clocale>

namespace lom::ui {

void useCNumberFormatForFiles() { std::setlocale(LC_NUMERIC, "C"); }

}  // namespace lom::ui
