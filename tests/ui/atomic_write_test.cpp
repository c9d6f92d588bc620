// Files the studio replaces (boxes, screenshots) are written to a temporary
// file, flushed and renamed into place: a failed write leaves the old file as
// it was, and a replaced file keeps its permissions.
#include <gtest/gtest.h>

#include <QImage>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "lom/atomic_file.hpp"
#include "lom/ui/window_capture.hpp"
#include "test_support.hpp"

namespace lom::ui {
namespace {

namespace fs = std::filesystem;

using lom::test::slurp;

size_t entriesIn(const fs::path& folder) {
  size_t count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) count += entry.exists();
  return count;
}

QString qPath(const fs::path& path) { return QString::fromStdString(path.string()); }

TEST(AtomicWrite, ReplacedFileKeepsItsPermissions) {
  lom::test::TempDir temp;
  const fs::path file = temp / "private.json";
  writeTextFileAtomically(file, "old");
  const fs::perms owner_only = fs::perms::owner_read | fs::perms::owner_write;
  fs::permissions(file, owner_only);
  writeTextFileAtomically(file, "new");
  EXPECT_EQ(slurp(file), "new");
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::mask, owner_only);

  fs::permissions(file, owner_only | fs::perms::group_read | fs::perms::others_read);
  writeTextFileAtomically(file, "newer");
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::mask,
            owner_only | fs::perms::group_read | fs::perms::others_read);
  EXPECT_EQ(entriesIn(temp.path()), 1u);  // no temporary file left
}

TEST(AtomicWrite, ScreenshotReplacesAPictureOnlyWithACompleteOne) {
  lom::test::TempDir temp;
  QImage image(32, 24, QImage::Format_RGB32);
  image.fill(Qt::darkCyan);

  const fs::path png = temp / "shot.png";
  ASSERT_EQ(saveImageAtomically(image, qPath(png)), QString());
  EXPECT_EQ(QImage(qPath(png)).size(), QSize(32, 24));

  // A format that cannot be written leaves the existing file as it was (a
  // direct QImage::save truncates it before finding out).
  const fs::path other = temp / "shot.not-an-image-format";
  std::ofstream(other) << "an earlier file";
  const QString error = saveImageAtomically(image, qPath(other));
  EXPECT_TRUE(error.contains("shot.not-an-image-format")) << error.toStdString();
  EXPECT_EQ(slurp(other), "an earlier file");
  EXPECT_EQ(entriesIn(temp.path()), 2u);  // no temporary file left
}

TEST(AtomicWrite, AScreenshotOnAFullDiskSaysSoAndKeepsTheOldPicture) {
  lom::test::TempDir temp;
  const fs::path png = temp / "shot.png";
  std::ofstream(png) << "an earlier picture";
  QImage image(256, 256, QImage::Format_RGB32);  // noise: its PNG takes far more than 1 KiB
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      image.setPixel(x, y, static_cast<QRgb>((x * 7919u + y * 104729u) * 2654435761u));
  // A limit on the size of any file written: a write beyond it fails as on a full disk.
  QString error;
  {
    const lom::test::FileSizeLimit full(1024);
    error = saveImageAtomically(image, qPath(png));
  }
  EXPECT_TRUE(error.contains("shot.png")) << error.toStdString();
  EXPECT_TRUE(error.contains("the file-size limit of 1 KiB set by ulimit -f?"))
      << error.toStdString();
  EXPECT_EQ(slurp(png), "an earlier picture");
  EXPECT_EQ(entriesIn(temp.path()), 1u);  // no temporary file left

  ASSERT_EQ(saveImageAtomically(image, qPath(png)), QString());  // room again
  EXPECT_EQ(QImage(qPath(png)).size(), QSize(256, 256));
  const QString no_extension = saveImageAtomically(image, qPath(temp / "shot"));
  EXPECT_TRUE(no_extension.contains("without an extension")) << no_extension.toStdString();
}

}  // namespace
}  // namespace lom::ui
