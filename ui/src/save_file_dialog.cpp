#include "lom/ui/save_file_dialog.hpp"

#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QMessageBox>

namespace lom::ui {

QString askSaveFileName(QWidget* parent, const QString& title, const QString& start,
                        const QString& filter, const QStringList& suffixes) {
  QFileDialog dialog(parent, title, start, filter);
  dialog.setAcceptMode(QFileDialog::AcceptSave);
  dialog.setFileMode(QFileDialog::AnyFile);
  // The dialog adds it to a name without a dot, and asks about that name.
  if (!suffixes.isEmpty()) dialog.setDefaultSuffix(suffixes.front());
  if (dialog.exec() != QDialog::Accepted) return {};
  const QStringList chosen = dialog.selectedFiles();
  if (chosen.isEmpty()) return {};
  QString path = chosen.front();
  // A name with a dot of its own ("shelf_0.005m") is left alone by the
  // dialog: it gets the suffix here, and the question the dialog would ask.
  if (suffixes.isEmpty() || suffixes.contains(QFileInfo(path).suffix(), Qt::CaseInsensitive))
    return path;
  path += "." + suffixes.front();
  if (QFileInfo::exists(path) &&
      QMessageBox::question(parent, title,
                            QObject::tr("%1 already exists.\nDo you want to replace it?")
                                .arg(QDir::toNativeSeparators(QFileInfo(path).fileName())),
                            QMessageBox::Yes | QMessageBox::No,
                            QMessageBox::No) != QMessageBox::Yes)
    return {};
  return path;
}

}  // namespace lom::ui
