// labeloctomap-studio: the desktop window.
//   labeloctomap-studio [--intrinsics K] [--map MAP.ot] [SEQ | --demo]
//   labeloctomap-studio --screenshot OUT.png [--frame N] [--fuse | --map MAP.ot] [--intrinsics K]
//                       (SEQ | --demo)
// Exit codes: 0 success, 1 unreadable or invalid input, 2 a mistake in the
// call, 3 no display to show the window on.
#include <QAction>
#include <QApplication>
#include <QCommandLineParser>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QImage>
#include <QThread>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "lom/atomic_file.hpp"
#include "lom/fusion.hpp"
#include "lom/import.hpp"
#include "lom/labels.hpp"
#include "lom/render/map_render.hpp"
#include "lom/ui/about_reaction.hpp"
#include "lom/ui/annotation_files.hpp"
#include "lom/ui/demo_scene.hpp"
#include "lom/ui/evaluation_panel.hpp"
#include "lom/ui/fusion_panel.hpp"
#include "lom/ui/main_window.hpp"
#include "lom/ui/map_worker.hpp"
#include "lom/ui/number_format.hpp"
#include "lom/ui/scene_view.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"
#include "lom/ui/window_capture.hpp"

namespace {

constexpr const char* kUsage =
    "usage: labeloctomap-studio [--intrinsics K] [--labels FILE] [--resolution R] [--max-range M]\n"
    "                           [--map MAP.ot] [SEQ | --demo]\n"
    "       labeloctomap-studio --screenshot OUT.png [--frame N] [--fuse | --map MAP.ot] "
    "[--intrinsics K]\n"
    "                           [--labels FILE] [--resolution R] [--max-range M] (SEQ | --demo)\n";

constexpr const char* kHelp =
    "LabelOctoMap Studio: view recorded RGB-D label sequences, fuse them into a labelled map,\n"
    "draw ground-truth boxes and score the map.\n"
    "\n"
    "Arguments:\n"
    "  SEQ                  Sequence folder or its sequence.json to open; a ROS bag or a dataset\n"
    "                       folder that `labeloctomap import` recognises is converted first.\n"
    "\n"
    "Options:\n"
    "  --demo               Generate (once, in the cache folder) and open a synthetic shelf-bin\n"
    "                       scene.\n"
    "  --intrinsics K       Camera of a dataset folder or bag that does not store it: fx,fy,cx,cy\n"
    "                       or a file with the 3x3 camera matrix (as `labeloctomap import`).\n"
    "  --labels FILE        Names of the label ids of a dataset folder or bag being converted,\n"
    "                       one per line from id 0, or apc2016 for the built-in APC 2016 set\n"
    "                       (as `labeloctomap import --labels`).\n"
    "  --resolution R       Voxel size to fuse with, in metres (0.002 to 1; default 0.01), as\n"
    "                       the Fusion panel's Resolution.\n"
    "  --max-range M        Max range to fuse with, in metres (0 = unlimited; default 1), as\n"
    "                       the Fusion panel's Max range (rays of at most 1000 voxels).\n"
    "  --screenshot OUT.png Open SEQ, save a picture of the window to OUT.png and exit.\n"
    "  --frame N            Frame to show, as the index N of frames[N] in sequence.json\n"
    "                       (default 0; the timeline shows frames[N] as frame N+1).\n"
    "  --fuse               With --screenshot: fuse the whole sequence before taking the picture.\n"
    "  --map MAP.ot         Show this map of SEQ, fused earlier (e.g. by labeloctomap fuse),\n"
    "                       instead of fusing SEQ (File > Open Map... in the window).\n"
    "  -h, --help           Show this help and exit.\n"
    "  -v, --version        Show the version and exit.\n"
    "\n"
    "Qt's own options (-platform, -display, -style, ...) are accepted too.\n"
    "Exit codes: 0 success, 1 unreadable or invalid input, 2 wrong call, 3 no display.\n";

struct StudioArguments {
  QString sequence;
  QString screenshot;
  int frame = 0;
  bool demo = false;
  bool fuse = false;
  QString map;  // --map
  std::optional<lom::CameraIntrinsics> intrinsics;
  std::optional<lom::LabelSet> labels;  // --labels
  std::optional<double> resolution, max_range;
  QString platform;  // -platform, when given
  QString display;   // -display, when given
};

enum class Request { Run, Help, Version };

// An exit code for the caller, or what to do.
struct Parsed {
  std::optional<int> exit_code;
  Request request = Request::Run;
};

int usageError(const std::string& message) {
  std::cerr << "labeloctomap-studio: " << message << "\n" << kUsage;
  return 2;
}

// Parsed before the QApplication exists, so that --help, --version and
// mistakes in the call are answered without a display.
Parsed parseArguments(const QStringList& words, StudioArguments& arguments) {
  QCommandLineParser parser;
  // Qt's options are single-dash words (-platform xcb): read them as long names.
  parser.setSingleDashWordOptionMode(QCommandLineParser::ParseAsLongOptions);
  const QCommandLineOption help_option(QStringList{"h", "help", "?"});
  const QCommandLineOption version_option(QStringList{"v", "version"});
  const QCommandLineOption screenshot_option("screenshot", "", "OUT.png");
  const QCommandLineOption frame_option("frame", "", "N");
  const QCommandLineOption demo_option("demo");
  const QCommandLineOption fuse_option("fuse");
  const QCommandLineOption intrinsics_option("intrinsics", "", "K");
  const QCommandLineOption map_option("map", "", "MAP.ot");
  const QCommandLineOption labels_option("labels", "", "FILE");
  const QCommandLineOption resolution_option("resolution", "", "R");
  const QCommandLineOption max_range_option("max-range", "", "M");
  const QCommandLineOption platform_option("platform", "", "NAME");
  const QCommandLineOption display_option("display", "", "NAME");
  parser.addOptions({help_option, version_option, screenshot_option, frame_option, demo_option,
                     fuse_option, intrinsics_option, map_option, labels_option, resolution_option,
                     max_range_option, platform_option, display_option});
  // The rest of QGuiApplication's and QApplication's options: QApplication
  // takes them, here they only must not count as mistakes.
  for (const char* name : {"platformpluginpath", "platformtheme", "plugin", "qwindowgeometry",
                           "geometry", "qwindowtitle", "title", "qwindowicon", "windowicon", "name",
                           "session", "style", "stylesheet", "qmljsdebugger"})
    parser.addOption(QCommandLineOption(name, "", "VALUE"));
  for (const char* name :
       {"reverse", "nograb", "dograb", "sync", "widgetcount", "testability", "qwindowsystem"})
    parser.addOption(QCommandLineOption(name));

  if (!parser.parse(words)) return {usageError(parser.errorText().toStdString()), Request::Run};
  if (parser.isSet(help_option)) return {std::nullopt, Request::Help};
  if (parser.isSet(version_option)) return {std::nullopt, Request::Version};

  const QStringList positional = parser.positionalArguments();
  if (positional.size() > 1) return {usageError("expected at most one sequence"), Request::Run};
  if (!positional.isEmpty()) arguments.sequence = positional.front();
  arguments.demo = parser.isSet(demo_option);
  arguments.fuse = parser.isSet(fuse_option);
  arguments.platform = parser.value(platform_option);
  arguments.display = parser.value(display_option);
  if (arguments.demo && !arguments.sequence.isEmpty())
    return {usageError("give either a sequence or --demo, not both"), Request::Run};
  arguments.screenshot = parser.value(screenshot_option);
  if (parser.isSet(screenshot_option) && arguments.screenshot.isEmpty())
    return {usageError("--screenshot: expected the picture's file name"), Request::Run};
  if (parser.isSet(frame_option)) {
    bool ok = false;
    arguments.frame = parser.value(frame_option).toInt(&ok);
    if (!ok || arguments.frame < 0)
      return {usageError("--frame: expected a frame index from 0 (below the sequence's frame "
                         "count), found '" +
                         parser.value(frame_option).toStdString() + "'"),
              Request::Run};
  }
  if (parser.isSet(screenshot_option) && arguments.sequence.isEmpty() && !arguments.demo)
    return {usageError("--screenshot needs a sequence to show"), Request::Run};
  if (parser.isSet(map_option)) {
    arguments.map = parser.value(map_option);
    if (arguments.map.isEmpty())
      return {usageError("--map: expected a map file (.ot)"), Request::Run};
    if (arguments.sequence.isEmpty() && !arguments.demo)
      return {usageError("--map needs the sequence the map was fused from (SEQ or --demo)"),
              Request::Run};
    if (arguments.fuse)
      return {usageError(
                  "give either --fuse (fuse the sequence) or --map (show a fused map), not both"),
              Request::Run};
  }
  // Fusion settings, checked as `labeloctomap fuse` checks them.
  auto number = [&](const QCommandLineOption& option, const char* name,
                    std::optional<double>& into) -> std::optional<int> {
    if (!parser.isSet(option)) return std::nullopt;
    bool ok = false;
    const double value = parser.value(option).toDouble(&ok);
    if (!ok || !std::isfinite(value))
      return usageError(std::string("--") + name + ": expected a number in metres, found '" +
                        parser.value(option).toStdString() + "'");
    into = value;
    return std::nullopt;
  };
  if (const auto code = number(resolution_option, "resolution", arguments.resolution))
    return {code, Request::Run};
  if (const auto code = number(max_range_option, "max-range", arguments.max_range))
    return {code, Request::Run};
  if (arguments.resolution && !(*arguments.resolution >= lom::kMinFusionResolution &&
                                *arguments.resolution <= lom::kMaxFusionResolution))
    return {usageError("--resolution: expected a voxel size from 0.002 to 1 m, found " +
                       parser.value(resolution_option).toStdString()),
            Request::Run};
  if (arguments.max_range && *arguments.max_range < 0.0)
    return {usageError("--max-range: expected a range in metres, 0 for unlimited, found " +
                       parser.value(max_range_option).toStdString()),
            Request::Run};
  if (const auto ray =
          lom::checkRayLength(arguments.max_range.value_or(lom::MapParameters{}.max_range),
                              arguments.resolution.value_or(lom::MapParameters{}.resolution)))
    return {
        usageError("--max-range and --resolution make rays " +
                   std::to_string(static_cast<long long>(ray->voxels)) + " voxels long; at most " +
                   std::to_string(static_cast<long long>(ray->limit)) +
                   " are allowed (a coarser --resolution or a shorter --max-range)"),
        Request::Run};
  if (parser.isSet(labels_option)) {
    const QString value = parser.value(labels_option);
    try {
      arguments.labels = lom::labelsOption(value.toStdString());
    } catch (const std::exception& error) {
      std::cerr << "labeloctomap-studio: --labels: " << error.what() << "\n";
      return {1, Request::Run};
    }
  }
  if (parser.isSet(intrinsics_option)) {
    const QString value = parser.value(intrinsics_option);
    try {
      arguments.intrinsics = lom::parseIntrinsics(value.toStdString());
    } catch (const std::exception& error) {
      // A file that cannot be read is bad input; anything else a wrong call.
      if (QFileInfo(value).isFile()) {
        std::cerr << "labeloctomap-studio: --intrinsics: " << error.what() << "\n";
        return {1, Request::Run};
      }
      return {usageError(std::string("--intrinsics: ") + error.what()), Request::Run};
    }
  }
  return {};
}

constexpr const char* kDisplayHint =
    "run it on a display or under a virtual X server, e.g. "
    "xvfb-run -a -s \"-screen 0 1280x1024x24\" labeloctomap-studio ... "
    "(for a picture of a fused map without the window, "
    "`labeloctomap render` does the same under xvfb-run)";

// Empty when Qt will find a display for the window; else why not. Qt aborts
// the process when its platform cannot connect, so this is asked first.
std::optional<std::string> displayProblem(const StudioArguments& arguments) {
  QString platforms = arguments.platform;
  if (platforms.isEmpty()) platforms = qEnvironmentVariable("QT_QPA_PLATFORM");
  if (platforms.isEmpty()) platforms = QStringLiteral("xcb");  // Qt 5's default on Linux
  const std::string display =
      (arguments.display.isEmpty() ? qEnvironmentVariable("DISPLAY") : arguments.display)
          .toStdString();
  std::string problem;
  for (const QString& entry : platforms.split(';', Qt::SkipEmptyParts)) {
    const QString name = entry.section(':', 0, 0).trimmed();
    if (name == QLatin1String("xcb")) {
      if (display.empty()) {
        problem = "the studio needs a display and DISPLAY is not set";
        continue;
      }
      if (lom::render::canOpenDisplay(display)) {
        if (lom::render::displayHasGlx(display)) return std::nullopt;
        problem = lom::render::missingGlxProblem("the studio's 3D view", display);
        continue;
      }
      problem = "the studio needs a display and cannot open display '" + display + "'";
    } else if (name.startsWith(QLatin1String("wayland"))) {
      if (!qEnvironmentVariable("WAYLAND_DISPLAY").isEmpty()) return std::nullopt;
      problem = "the studio needs a display and WAYLAND_DISPLAY is not set";
    } else if (name == QLatin1String("offscreen") || name == QLatin1String("minimal")) {
      problem = "the studio's 3D view needs OpenGL, which the Qt platform '" + name.toStdString() +
                "' (QT_QPA_PLATFORM or -platform) does not give";
    } else {
      return std::nullopt;  // vnc, eglfs, linuxfb...: a platform chosen on purpose
    }
  }
  return problem + "; " + kDisplayHint;
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

constexpr qint64 kFusionTimeoutMs = 30 * 60 * 1000;

// Runs the event loop while `busy` holds, for at most kFusionTimeoutMs;
// false when it still holds then.
template <class Busy>
bool waitWhile(Busy busy) {
  QElapsedTimer timer;
  timer.start();
  while (busy() && timer.elapsed() < kFusionTimeoutMs) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    QThread::msleep(10);
  }
  return !busy();
}

// False when fusion did not end in time.
bool waitForFusion(lom::ui::MainWindow& window) {
  QElapsedTimer timer;
  timer.start();
  if (!waitWhile([&] { return window.session().worker().isFusing(); })) return false;
  // Let the last snapshot and the evaluation it triggers reach the views.
  for (int i = 0; i < 50 || window.evaluationPanel().isBusy(); ++i) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    QThread::msleep(10);
    if (timer.elapsed() > kFusionTimeoutMs) break;
  }
  // The map, and the camera of the frame shown, which --frame chose.
  window.sceneView().zoomToMap(/*with_current_camera=*/true);
  return true;
}

// `failed` turns true when the window reports an error (an unreadable frame or
// boxes file, fusion stopped): the picture would not show what was asked for.
// The file of the sequence that `shot` would replace; empty when it is none
// of them. (A converted recording's own files are not known here: the
// conversion read them into the cache.)
std::string inputAt(const std::filesystem::path& shot,
                    const lom::ui::SequenceController& controller) {
  namespace fs = std::filesystem;
  const QString file = controller.sequenceFileAt(QString::fromStdString(shot.string()));
  if (!file.isEmpty()) return file.toStdString();
  const fs::path boxes = controller.sequence().root / "annotations.json";
  std::error_code ec;
  return fs::equivalent(shot, boxes, ec) ? boxes.string() : std::string();
}

// Reads the --map file into the window once the sequence is open; false when
// reading did not end in time (an unreadable map is an error the window reports).
bool openMapAndWait(lom::ui::MainWindow& window, const QString& map) {
  window.session().openMap(map);
  return waitWhile([&] { return window.session().isOpeningMap(); }) && waitForFusion(window);
}

int saveScreenshot(lom::ui::MainWindow& window, const StudioArguments& arguments,
                   const bool& failed) {
  auto& controller = window.controller();
  // A picture format first, as `labeloctomap render` checks its --out: a
  // mistake in the call, found before any fusion.
  if (!lom::ui::namesWritableImageFormat(arguments.screenshot)) {
    std::cerr << "labeloctomap-studio: --screenshot " << arguments.screenshot.toStdString()
              << ": expected a file name ending in an image format such as .png or .jpg\n";
    return 2;
  }
  // ... and where it goes: a missing folder found only after the fusion
  // would waste it.
  {
    const QFileInfo target(arguments.screenshot);
    const QFileInfo folder(target.absolutePath());
    if (target.isDir() || !folder.isDir() || !folder.isWritable()) {
      std::cerr << "labeloctomap-studio: --screenshot " << arguments.screenshot.toStdString()
                << ": expected a file in an existing, writable folder; "
                << (target.isDir() ? "it is a folder"
                    : !folder.exists()
                        ? "its folder " + folder.filePath().toStdString() + " does not exist"
                    : !folder.isDir()
                        ? folder.filePath().toStdString() + " is not a folder"
                        : "its folder " + folder.filePath().toStdString() + " is not writable")
                << "\n";
      return 2;
    }
  }
  window.session().setAutoFuse(arguments.fuse);
  if (!controller.openSequence(arguments.sequence)) return 1;
  if (arguments.frame >= controller.frameCount()) {
    std::cerr << "labeloctomap-studio: --frame " << arguments.frame << ": the sequence has "
              << controller.frameCount() << " frames (indices 0.." << controller.frameCount() - 1
              << ")\n";
    return 2;
  }
  if (const std::string input = inputAt(arguments.screenshot.toStdString(), controller);
      !input.empty()) {
    std::cerr << "labeloctomap-studio: --screenshot " << arguments.screenshot.toStdString()
              << " would replace the input " << input << "; choose another file name\n";
    return 2;
  }
  if (arguments.intrinsics && !controller.isConverted())
    std::cerr << "labeloctomap-studio: note: --intrinsics is not used: "
              << controller.sequencePath().toStdString()
              << " is a sequence with its own camera (it applies to recordings being converted)\n";
  if (arguments.labels && !controller.isConverted())
    std::cerr << "labeloctomap-studio: note: --labels is not used: "
              << controller.sequencePath().toStdString()
              << " is a sequence with its own labels (it applies to recordings being converted)\n";
  controller.setCurrentFrame(arguments.frame);
  if (!arguments.map.isEmpty()) {
    if (QAction* points = window.findAction("Show Frame Points"); points && points->isChecked())
      points->trigger();
    if (!openMapAndWait(window, arguments.map)) {
      std::cerr << "labeloctomap-studio: reading the map did not finish within 30 minutes; no "
                   "picture written\n";
      return 1;
    }
  }
  if (arguments.fuse) {
    // A picture of the fused map: the map's voxels without the frame's points.
    if (QAction* points = window.findAction("Show Frame Points"); points && points->isChecked())
      points->trigger();
    if (!waitForFusion(window)) {
      std::cerr << "labeloctomap-studio: fusion did not finish within 30 minutes; no picture "
                   "written\n";
      return 1;
    }
    // What the Fusion panel says about the depths max range left out (its
    // button to re-fuse cannot be pressed in a picture run).
    if (const QString note = window.fusionPanel().rangeNote(); !note.isEmpty())
      std::cerr << "labeloctomap-studio: warning: " << note.toStdString()
                << " Give --max-range (and --resolution) to fuse farther.\n";
  }
  if (!lom::ui::waitUntilExposed(window))
    std::cerr << "labeloctomap-studio: warning: the window was not shown on screen in time\n";
  if (failed) {
    std::cerr << "labeloctomap-studio: no picture written to " << arguments.screenshot.toStdString()
              << " because of the error above\n";
    return 1;
  }
  const QImage shot = lom::ui::captureWindow(window, window.sceneView());
  const QString error = lom::ui::saveImageAtomically(shot, arguments.screenshot);
  if (!error.isEmpty()) {
    std::cerr << "labeloctomap-studio: " << error.toStdString() << "\n";
    return 1;
  }
  std::cout << "saved " << arguments.screenshot.toStdString() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) makes writes fail with EFBIG, reported like
  // a full disk, instead of killing the studio with unsaved work (SIGXFSZ).
  std::signal(SIGXFSZ, SIG_IGN);
  // A kill in the middle of a save removes the temporary file (the saved file
  // is intact: it is replaced only by a complete one).
  lom::removePendingOutputsOnSignals();
  QStringList words;
  for (int i = 0; i < argc; ++i) words << QString::fromLocal8Bit(argv[i]);
  StudioArguments arguments;
  const Parsed parsed = parseArguments(words, arguments);
  if (parsed.exit_code) return *parsed.exit_code;
  if (parsed.request == Request::Help) {
    std::cout << kUsage << "\n" << kHelp;
    return 0;
  }
  if (parsed.request == Request::Version) {
    std::cout << "labeloctomap-studio " << lom::ui::studioVersion().toStdString() << "\n";
    return 0;
  }
  if (const auto problem = displayProblem(arguments)) {
    std::cerr << "labeloctomap-studio: " << *problem << "\n";
    return 3;
  }

  lom::ui::setDefaultSurfaceFormat();
  QApplication app(argc, argv);
  lom::ui::useCNumberFormat();
  QApplication::setOrganizationName("LabelOctoMap");
  QApplication::setApplicationName("LabelOctoMap Studio");
  QApplication::setApplicationVersion(lom::ui::studioVersion());
  if (!resolveDemo(arguments)) return 1;

  lom::ui::MainWindow window;
  if (arguments.intrinsics || arguments.labels) {
    lom::ImportOptions import = window.controller().importOptions();
    if (arguments.intrinsics) import.intrinsics = arguments.intrinsics;
    if (arguments.labels) import.labels = arguments.labels;
    window.controller().setImportOptions(import);
  }
  if (arguments.resolution || arguments.max_range) {
    lom::FusionOptions fusion = window.session().fusionOptions();
    if (arguments.resolution) fusion.map.resolution = *arguments.resolution;
    if (arguments.max_range) fusion.map.max_range = *arguments.max_range;
    window.session().setFusionOptions(fusion);
  }
  if (!arguments.screenshot.isEmpty()) {
    // No one is there to close a dialog: errors go to stderr and the exit code.
    bool failed = false;
    window.recentSequences().freeze();  // a picture taken is not a session to reopen
    // ... nor one that reads or leaves the labels a recording was converted with.
    window.controller().setRemembersConversions(false);
    // Unsaved boxes of an earlier session stay for the next interactive one.
    window.autosave().leaveRecoveryFilesAlone();
    window.setWarningReporter([](const QString& title, const QString& message) {
      std::cerr << "labeloctomap-studio: warning: " << title.toStdString() << ": "
                << message.toStdString() << "\n";
    });
    window.setErrorReporter([&failed](const QString& title, const QString& message) {
      std::cerr << "labeloctomap-studio: " << title.toStdString() << ": " << message.toStdString()
                << "\n";
      failed = true;
    });
    window.show();
    return saveScreenshot(window, arguments, failed);
  }

  window.rememberLayout();
  window.show();
  window.session().setAutoFuse(arguments.map.isEmpty());
  if (arguments.fuse)
    std::cerr << "labeloctomap-studio: note: --fuse applies to --screenshot runs; the studio "
                 "fuses a sequence it opens anyway\n";
  if (!arguments.sequence.isEmpty() && window.controller().openSequence(arguments.sequence)) {
    if (arguments.frame >= window.controller().frameCount())
      std::cerr << "labeloctomap-studio: warning: --frame " << arguments.frame
                << ": the sequence has " << window.controller().frameCount()
                << " frames (indices 0.." << window.controller().frameCount() - 1
                << "); showing the last\n";
    window.controller().setCurrentFrame(arguments.frame);
    if (!arguments.map.isEmpty()) window.session().openMap(arguments.map);
  }
  window.session().setAutoFuse(true);
  // Closed while the recording was being converted: there is nothing left to
  // run (Qt quits on the last window only once its event loop runs).
  if (!window.isVisible()) return 0;
  return QApplication::exec();
}
