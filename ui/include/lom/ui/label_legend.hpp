#pragma once
#include <QColor>
#include <QString>
#include <QWidget>
#include <vector>

namespace lom::ui {

// Colour swatches with label names, flowing over as many rows as needed.
// Long names are elided with "…" and told whole in a tooltip.
class LabelLegend : public QWidget {
  Q_OBJECT

 public:
  struct Entry {
    QColor color;
    QString name;
  };

  explicit LabelLegend(QWidget* parent = nullptr);

  void setEntries(std::vector<Entry> entries);
  // Shown when there are no entries, e.g. "only background".
  void setNote(const QString& note);
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
  // The names as drawn at the legend's present width (elided when too long).
  [[nodiscard]] std::vector<QString> shownNames() const;
  // The tooltip at `point`: the whole name of an elided entry there, else empty.
  [[nodiscard]] QString toolTipAt(const QPoint& point) const;

  [[nodiscard]] bool hasHeightForWidth() const override { return true; }
  [[nodiscard]] int heightForWidth(int width) const override;
  [[nodiscard]] QSize sizeHint() const override { return {240, heightForWidth(240)}; }

 protected:
  bool event(QEvent* event) override;
  void paintEvent(QPaintEvent* event) override;

 private:
  // Calls place(entry, shown name, rect, swatch size) for each entry laid out in
  // `width`; returns the height used.
  template <typename Place>
  int layOut(int width, Place place) const;

  std::vector<Entry> entries_;
  QString note_;
};

}  // namespace lom::ui
