#pragma once
#include <QColor>
#include <QString>
#include <QWidget>
#include <vector>

namespace lom::ui {

// Colour swatches with label names, flowing over as many rows as needed.
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

  [[nodiscard]] bool hasHeightForWidth() const override { return true; }
  [[nodiscard]] int heightForWidth(int width) const override;
  [[nodiscard]] QSize sizeHint() const override { return {240, heightForWidth(240)}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  // Calls place(entry, rect) for each entry laid out in `width`; returns the height used.
  template <typename Place>
  int layOut(int width, Place place) const;

  std::vector<Entry> entries_;
  QString note_;
};

}  // namespace lom::ui
