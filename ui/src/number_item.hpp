#pragma once
// A table cell that shows a number as text of the panel's choosing (a fixed
// number of decimals, percent) and sorts by the exact value, kept under
// kNumberValueRole.
#include <QTableWidgetItem>

namespace lom::ui {

inline constexpr int kNumberValueRole = Qt::UserRole + 1;

class NumberItem : public QTableWidgetItem {
 public:
  NumberItem(double value, const QString& text) : QTableWidgetItem(text) {
    setData(kNumberValueRole, value);
    setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
  }
  [[nodiscard]] bool operator<(const QTableWidgetItem& other) const override {
    return data(kNumberValueRole).toDouble() < other.data(kNumberValueRole).toDouble();
  }
};

// A count, shown as it is.
inline QTableWidgetItem* countItem(size_t count) {
  return new NumberItem(static_cast<double>(count), QString::number(count));
}

}  // namespace lom::ui
