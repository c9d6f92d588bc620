#include "lom/ui/shortcuts_help_reaction.hpp"

#include <QAbstractButton>
#include <QAction>
#include <QDialog>
#include <QDialogButtonBox>
#include <QHeaderView>
#include <QScreen>
#include <QTableWidget>
#include <QVBoxLayout>
#include <QWidget>

namespace lom::ui {

ShortcutsHelpReaction::ShortcutsHelpReaction(QAction* action, QWidget* window)
    : Reaction(action), window_(window) {}

QStringList ShortcutsHelpReaction::rows() const {
  QStringList rows;
  for (const QAction* action : window_->findChildren<QAction*>()) {
    if (action->shortcut().isEmpty()) continue;
    // Every key of the action (Redo: Ctrl+Shift+Z, Ctrl+Y).
    QStringList keys;
    for (const QKeySequence& key : action->shortcuts())
      keys << key.toString(QKeySequence::NativeText);
    const QString row = keys.join(", ") + "\t" + action->text().remove('&');
    if (!rows.contains(row)) rows << row;
  }
  // Buttons with their own key (play / pause: Space), named by their text or,
  // for icon buttons, by their tooltip without the key in parentheses.
  for (const QAbstractButton* button : window_->findChildren<QAbstractButton*>()) {
    if (button->shortcut().isEmpty()) continue;
    const QString keys = button->shortcut().toString(QKeySequence::NativeText);
    QString name = button->text().remove('&');
    if (name.isEmpty()) name = button->toolTip().remove(" (" + keys + ")");
    const QString row = keys + "\t" + name;
    if (!rows.contains(row)) rows << row;
  }
  return rows;
}

void ShortcutsHelpReaction::onTriggered() {
  QDialog dialog(window_);
  dialog.setWindowTitle(tr("Keyboard Shortcuts"));
  const QStringList lines = rows();
  auto* table = new QTableWidget(lines.size(), 2);
  table->setHorizontalHeaderLabels({tr("Keys"), tr("Action")});
  table->verticalHeader()->hide();
  table->horizontalHeader()->setStretchLastSection(true);
  table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  for (int row = 0; row < lines.size(); ++row) {
    const QStringList parts = lines[row].split('\t');
    table->setItem(row, 0, new QTableWidgetItem(parts.value(0)));
    table->setItem(row, 1, new QTableWidgetItem(parts.value(1)));
  }
  table->resizeColumnToContents(0);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  QObject::connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  auto* layout = new QVBoxLayout(&dialog);
  layout->addWidget(table);
  layout->addWidget(buttons);
  // At most the screen's free area (large scale factors, small screens):
  // the Close button must stay on screen.
  QSize size(460, 560);
  if (const QScreen* screen = window_->screen())
    size = size.boundedTo(screen->availableGeometry().size() * 0.9);
  dialog.resize(size);
  dialog.exec();
}

}  // namespace lom::ui
