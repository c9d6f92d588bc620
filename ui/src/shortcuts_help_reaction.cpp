#include "lom/ui/shortcuts_help_reaction.hpp"

#include <QAbstractButton>
#include <QAction>
#include <QDialog>
#include <QDialogButtonBox>
#include <QHeaderView>
#include <QScreen>
#include <QStyle>
#include <QTableWidget>
#include <QVBoxLayout>
#include <QWidget>
#include <algorithm>

namespace lom::ui {

ShortcutsHelpReaction::ShortcutsHelpReaction(QAction* action, QWidget* window)
    : Reaction(action), window_(window) {}

QStringList ShortcutsHelpReaction::rows() const {
  QStringList rows;
  for (const QAction* action : window_->findChildren<QAction*>()) {
    if (action->shortcut().isEmpty()) continue;
    // Every key of the action (Redo: Ctrl+Shift+Z, Ctrl+Y).
    // Qt's own aliases (Ctrl+Shift+Backtab for Ctrl+Shift+Tab) are no key
    // of their own to a user.
    QStringList keys;
    for (const QKeySequence& key : action->shortcuts()) {
      const QString text = key.toString(QKeySequence::NativeText);
      if (!text.contains("Backtab") || action->shortcuts().size() == 1) keys << text;
    }
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

std::unique_ptr<QDialog> ShortcutsHelpReaction::createDialog() const {
  auto owned = std::make_unique<QDialog>(window_);
  QDialog& dialog = *owned;
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
  table->resizeColumnsToContents();
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  QObject::connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  auto* layout = new QVBoxLayout(&dialog);
  layout->addWidget(table);
  layout->addWidget(buttons);
  // Both columns whole (the action names were cut off in a fixed width), at
  // most the screen's free area (large scale factors, small screens): the
  // Close button must stay on screen.
  const QMargins margins = layout->contentsMargins();
  const int width = table->horizontalHeader()->length() + 2 * table->frameWidth() +
                    table->style()->pixelMetric(QStyle::PM_ScrollBarExtent) + margins.left() +
                    margins.right() + 8;
  QSize size(std::max(460, width), 560);
  if (const QScreen* screen = window_->screen())
    size = size.boundedTo(screen->availableGeometry().size() * 0.9);
  dialog.resize(size);
  return owned;
}

void ShortcutsHelpReaction::onTriggered() { createDialog()->exec(); }

}  // namespace lom::ui
