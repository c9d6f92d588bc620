// The GUI tests need one QApplication for the whole run, created after the
// OpenGL surface format VTK needs has been made the default.
#include <gtest/gtest.h>

#include <QApplication>
#include <QTemporaryDir>

#include "lom/ui/number_format.hpp"
#include "lom/ui/scene_view.hpp"

int main(int argc, char** argv) {
  // Recent-file lists go to a throw-away settings folder, not the user's.
  QTemporaryDir settings_home;
  qputenv("XDG_CONFIG_HOME", settings_home.path().toLocal8Bit());
  // Recovery files and the demo cache likewise.
  QTemporaryDir data_home, cache_home;
  qputenv("XDG_DATA_HOME", data_home.path().toLocal8Bit());
  qputenv("XDG_CACHE_HOME", cache_home.path().toLocal8Bit());

  lom::ui::setDefaultSurfaceFormat();
  QApplication app(argc, argv);
  lom::ui::useCNumberFormat();
  QApplication::setOrganizationName("LabelOctoMapTests");
  QApplication::setApplicationName("lom_ui_tests");
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
