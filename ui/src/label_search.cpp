#include "label_search.hpp"

#include <QComboBox>
#include <QElapsedTimer>
#include <QKeyEvent>
#include <QStandardItemModel>

namespace lom::ui {

namespace {

// A label drop-down with the focus takes the letters typed into it (Qt's
// search by name) instead of the window's one-key box edits (W moves a box,
// B adds one), which would otherwise edit the box while the user picks a label.
std::optional<bool> takeTypedLetters(const QKeyEvent& key) {
  const Qt::KeyboardModifiers chords = Qt::ControlModifier | Qt::AltModifier | Qt::MetaModifier;
  if ((key.modifiers() & chords) || key.text().isEmpty() || !key.text().at(0).isPrint())
    return std::nullopt;
  return true;
}

// Letters typed into a label drop-down find a label by its name: the entries
// start with the label's number ("10 dove_beauty_bar"), so Qt's own search by
// first letter never matched a letter. Letters typed within a second add up
// ("do" finds dove_beauty_bar past dasani_water_bottle); the choice counts as
// the user's (activated).
class LabelNameSearch : public QObject {
 public:
  explicit LabelNameSearch(QObject* parent) : QObject(parent) {}

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() != QEvent::KeyPress) return false;
    auto* combo = qobject_cast<QComboBox*>(watched);
    const auto* key = static_cast<QKeyEvent*>(event);
    if (!combo || !takeTypedLetters(*key) || !key->text().at(0).isLetter()) return false;
    if (!typed_.isValid() || typed_.elapsed() > 1000 || watched != last_) prefix_.clear();
    typed_.start();
    last_ = watched;
    const QString letter = key->text().toLower();
    prefix_ += letter;
    // As Qt's own search: when the letters so far match nothing, the last one
    // starts again.
    if (!select(*combo, prefix_) && prefix_ != letter) {
      prefix_ = letter;
      select(*combo, prefix_);
    }
    return true;
  }

 private:
  // The first enabled entry whose name starts with `prefix`, chosen; false
  // when there is none.
  static bool select(QComboBox& combo, const QString& prefix) {
    const auto* model = qobject_cast<const QStandardItemModel*>(combo.model());
    for (int i = 0; i < combo.count(); ++i) {
      const QString text = combo.itemText(i);
      const bool enabled = !model || !model->item(i) || model->item(i)->isEnabled();
      if (!enabled || !text.mid(text.indexOf(' ') + 1).toLower().startsWith(prefix)) continue;
      if (i != combo.currentIndex()) {
        combo.setCurrentIndex(i);
        emit combo.activated(i);
      }
      return true;
    }
    return false;
  }

  QString prefix_;
  QElapsedTimer typed_;
  QObject* last_ = nullptr;
};

}  // namespace

void searchLabelsByName(QComboBox& combo) {
  combo.installEventFilter(new ShortcutKeys(&combo, takeTypedLetters));
  combo.installEventFilter(new LabelNameSearch(&combo));
}

}  // namespace lom::ui
