#pragma once
// Keeping long label names (some datasets have names of 100+ characters) from
// widening docks or being cut mid-word: they are elided with "…" and told
// whole in a tooltip.
#include <QComboBox>
#include <QString>

namespace lom::ui {

// `name` cut to at most `max_characters` characters, the last one "…", for
// messages and texts that wrap (where a long name would be one unbreakable word).
[[nodiscard]] QString shortName(const QString& name, int max_characters = 32);

// A combo box whose width does not follow its longest item: the current item
// is drawn elided with "…" when it does not fit, and told whole in a tooltip.
class ElidingComboBox : public QComboBox {
  Q_OBJECT

 public:
  explicit ElidingComboBox(QWidget* parent = nullptr);

  // The current item's text as drawn at the present width.
  [[nodiscard]] QString shownText() const;
  // The tooltip: the current item's whole text when it is elided, else empty.
  [[nodiscard]] QString elidedToolTip() const;

 protected:
  bool event(QEvent* event) override;
  void paintEvent(QPaintEvent* event) override;

 private:
  [[nodiscard]] int textWidth() const;
};

}  // namespace lom::ui
