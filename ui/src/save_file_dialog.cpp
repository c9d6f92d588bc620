#include "lom/ui/save_file_dialog.hpp"

#include <QFileDialog>
#include <QStringList>

namespace lom::ui {

QString askSaveFileName(QWidget* parent, const QString& title, const QString& start,
                        const QString& filter, const QString& default_suffix) {
  QFileDialog dialog(parent, title, start, filter);
  dialog.setAcceptMode(QFileDialog::AcceptSave);
  dialog.setFileMode(QFileDialog::AnyFile);
  dialog.setDefaultSuffix(default_suffix);
  if (dialog.exec() != QDialog::Accepted) return {};
  const QStringList chosen = dialog.selectedFiles();
  return chosen.isEmpty() ? QString() : chosen.front();
}

}  // namespace lom::ui
