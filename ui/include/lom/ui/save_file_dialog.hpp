#pragma once
#include <QString>

class QWidget;

namespace lom::ui {

// Asks where to save, as QFileDialog::getSaveFileName does, and adds
// `default_suffix` ("ply", no dot) to a name typed without one, as save
// dialogs do; the dialog then asks before replacing the file of the full
// name. An empty result is a cancelled dialog.
[[nodiscard]] QString askSaveFileName(QWidget* parent, const QString& title, const QString& start,
                                      const QString& filter, const QString& default_suffix);

}  // namespace lom::ui
