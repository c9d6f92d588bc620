#pragma once
#include <QString>
#include <QStringList>

class QWidget;

namespace lom::ui {

// Asks where to save, as QFileDialog::getSaveFileName does, and gives a name
// typed without one of `suffixes` ("ply", no dot; any case) the first of
// them, as save dialogs do: "map" and "shelf_0.005m" become "map.ply" and
// "shelf_0.005m.ply". A name given a suffix that way that is an existing file
// is asked about before it is replaced. An empty result is a cancelled dialog
// (or a replacement declined).
[[nodiscard]] QString askSaveFileName(QWidget* parent, const QString& title, const QString& start,
                                      const QString& filter, const QStringList& suffixes);

}  // namespace lom::ui
