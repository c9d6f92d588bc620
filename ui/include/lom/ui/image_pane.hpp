#pragma once
#include <QImage>
#include <QString>
#include <QWidget>

namespace lom::ui {

// One captioned 2D image, scaled to fit while keeping its aspect ratio.
class ImagePane : public QWidget {
  Q_OBJECT

 public:
  explicit ImagePane(const QString& caption, QWidget* parent = nullptr);

  void setImage(const QImage& image);
  // Shown instead of an image, e.g. "no colour image in this frame".
  void setPlaceholder(const QString& text);
  // Elided with "…" when the pane is too narrow; the caption row's tooltip then tells it whole.
  void setCaption(const QString& caption);
  [[nodiscard]] const QString& caption() const { return caption_; }
  // The caption as drawn at the pane's present width.
  [[nodiscard]] QString shownCaption() const;
  // The tooltip of the caption row: the whole caption when it is elided, else empty.
  [[nodiscard]] QString captionToolTip() const;
  [[nodiscard]] const QImage& image() const { return image_; }

  [[nodiscard]] QSize sizeHint() const override { return {320, 260}; }
  [[nodiscard]] QSize minimumSizeHint() const override { return {120, 90}; }
  [[nodiscard]] bool hasHeightForWidth() const override { return false; }

 signals:
  // The image pixel under the mouse, or (-1, -1) when it leaves the image.
  void hovered(const QPoint& pixel);

 protected:
  bool event(QEvent* event) override;
  void paintEvent(QPaintEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void leaveEvent(QEvent* event) override;

 private:
  [[nodiscard]] QRect imageRect() const;
  // The device pixels (HiDPI) the image is drawn into at `target`.
  [[nodiscard]] QSize deviceSizeOf(const QRect& target) const;
  [[nodiscard]] int captionHeight() const;

  QString caption_;
  QString placeholder_;
  QImage image_;
  QImage drawn_;  // image_ sampled to the device pixels it was last drawn into
};

}  // namespace lom::ui
