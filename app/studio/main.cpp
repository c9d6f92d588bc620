// labeloctomap-studio: the desktop window.
//   labeloctomap-studio [SEQ | --demo]
//   labeloctomap-studio --screenshot OUT.png [--frame N] [--fuse] (SEQ | --demo)
#include <QAction>
#include <QApplication>
#include <QCommandLineParser>
#include <QImage>
#include <QElapsedTimer>
#include <QThread>
#include <iostream>

#include "lom/ui/about_reaction.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/window_capture.hpp"

namespace {

struct StudioArguments {
  QString sequence;
  QString screenshot;
  int frame = 0;
  bool demo = false;
  bool fuse = false;
};

int usageError(const QString& message) {
  std::cerr << "labeloctomap-studio: " << message.toStdString()
            << "\nusage: labeloctomap-studio [SEQ | --demo]\n"
               "       labeloctomap-studio --screenshot OUT.png [--frame N] [--fuse] (SEQ | --demo)\n";
  return 2;
}

// Returns an exit code when the arguments are unusable.
std::optional<int> parseArguments(const QApplication& app, StudioArguments& arguments) {
  QCommandLineParser parser;
  parser.setApplicationDescription("LabelOctoMap Studio: view recorded RGB-D label sequences.");
  parser.addHelpOption();
  parser.addVersionOption();
  parser.addPositionalArgument("SEQ", "Sequence folder or its sequence.json to open.", "[SEQ]");
  const QCommandLineOption screenshot_option(
      "screenshot", "Open SEQ, save a picture of the window to OUT.png and exit.", "OUT.png");
  const QCommandLineOption frame_option(
      "frame", "Frame to show, as the index N of frames[N] in sequence.json (default 0).", "N");
  const QCommandLineOption demo_option(
      "demo", "Generate (once, in the cache folder) and open a synthetic shelf-bin scene.");
  const QCommandLineOption fuse_option(
      "fuse", "With --screenshot: fuse the whole sequence before taking the picture.");
  parser.addOptions({screenshot_option, frame_option, demo_option, fuse_option});
  parser.process(app);  // exits itself on --help, --version and unknown options

  const QStringList positional = parser.positionalArguments();
  if (positional.size() > 1) return usageError("expected at most one sequence");
  if (!positional.isEmpty()) arguments.sequence = positional.front();
  arguments.demo = parser.isSet(demo_option);
  arguments.fuse = parser.isSet(fuse_option);
  if (arguments.demo && !arguments.sequence.isEmpty())
    return usageError("give either a sequence or --demo, not both");
  arguments.screenshot = parser.value(screenshot_option);
  if (parser.isSet(frame_option)) {
    bool ok = false;
    arguments.frame = parser.value(frame_option).toInt(&ok);
    if (!ok || arguments.frame < 0)
      return usageError("--frame: expected a frame index >= 0, found '" +
                        parser.value(frame_option) + "'");
  }
  if (parser.isSet(screenshot_option) && arguments.sequence.isEmpty() && !arguments.demo)
    return usageError("--screenshot needs a sequence to show");
  return std::nullopt;
}

// Returns false when the demo scene cannot be written.
bool resolveDemo(StudioArguments& arguments) {
  if (!arguments.demo) return true;
  try {
    arguments.sequence = lom::ui::prepareDemoScene(lom::ui::defaultDemoFolder());
  } catch (const std::exception& error) {
    std::cerr << "labeloctomap-studio: cannot write the demo scene: " << error.what() << "\n";
    return false;
  }
  return true;
}

void waitForFusion(lom::ui::MainWindow& window) {
  QElapsedTimer timer;
  timer.start();
  while (window.session().worker().isFusing() && timer.elapsed() < 30 * 60 * 1000) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    QThread::msleep(10);
  }
  // Let the last snapshot and the evaluation it triggers reach the views.
  for (int i = 0; i < 50 || window.evaluationPanel().isBusy(); ++i) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    QThread::msleep(10);
    if (timer.elapsed() > 30 * 60 * 1000) break;
  }
  window.sceneView().zoomToMap();
}

int saveScreenshot(lom::ui::MainWindow& window, const StudioArguments& arguments) {
  auto& controller = window.controller();
  window.session().setAutoFuse(arguments.fuse);
  if (!controller.openSequence(arguments.sequence)) return 1;
  if (arguments.frame >= controller.frameCount()) {
    std::cerr << "labeloctomap-studio: --frame " << arguments.frame << ": the sequence has "
              << controller.frameCount() << " frames (indices 0.." << controller.frameCount() - 1
              << ")\n";
    return 2;
  }
  controller.setCurrentFrame(arguments.frame);
  if (arguments.fuse) {
    // A picture of the fused map: the map's voxels without the frame's points.
    if (QAction* points = window.findAction("Show Frame Points"); points && points->isChecked())
      points->trigger();
    waitForFusion(window);
  }
  if (!lom::ui::waitUntilExposed(window))
    std::cerr << "labeloctomap-studio: warning: the window was not shown on screen in time\n";
  const QImage shot = lom::ui::captureWindow(window, window.sceneView());
  if (!shot.save(arguments.screenshot)) {
    std::cerr << "labeloctomap-studio: cannot write " << arguments.screenshot.toStdString()
              << " (check the folder exists and is writable, and the extension is an image "
                 "format such as .png)\n";
    return 1;
  }
  std::cout << "saved " << arguments.screenshot.toStdString() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  lom::ui::setDefaultSurfaceFormat();
  QApplication app(argc, argv);
  QApplication::setOrganizationName("LabelOctoMap");
  QApplication::setApplicationName("LabelOctoMap Studio");
  QApplication::setApplicationVersion(lom::ui::studioVersion());

  StudioArguments arguments;
  if (const auto exit_code = parseArguments(app, arguments)) return *exit_code;
  if (!resolveDemo(arguments)) return 1;

  lom::ui::MainWindow window;
  if (!arguments.screenshot.isEmpty()) {
    // No one is there to close a dialog: errors go to stderr and the exit code.
    window.setErrorReporter([](const QString& title, const QString& message) {
      std::cerr << "labeloctomap-studio: " << title.toStdString() << ": " << message.toStdString()
                << "\n";
    });
    window.show();
    return saveScreenshot(window, arguments);
  }

  window.show();
  if (!arguments.sequence.isEmpty() && window.controller().openSequence(arguments.sequence))
    window.controller().setCurrentFrame(arguments.frame);
  return QApplication::exec();
}
