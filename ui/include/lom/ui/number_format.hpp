#pragma once

namespace lom::ui {

// Must run right after the QApplication is created: Qt sets the C library's
// locale from the environment, and under a German or French number format
// the core's strtod and snprintf would read "615.19" as 615 and write
// "0,24" into reports and OBJ meshes. The studio's files and the files it
// reads use the C number format, as the command-line program's do (the
// widgets format numbers with QString::number, which never used the locale).
void useCNumberFormatForFiles();

}  // namespace lom::ui
