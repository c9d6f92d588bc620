#pragma once

namespace lom::ui {

// Must run right after the QApplication is created. Qt sets the C library's
// locale from the environment, and under a German or French number format
// the core's strtod and snprintf would read "615.19" as 615 and write "0,24"
// into reports and OBJ meshes; and Qt's default locale would make the number
// fields show and expect "0,010" beside tables, legends and files that say
// "0.010". So the studio reads, writes, shows and takes numbers with a
// decimal point everywhere, as the command-line program does.
void useCNumberFormat();

}  // namespace lom::ui
