// Whether an X display can be opened, checked before VTK tries (Debian's VTK
// renders through X and aborts the process when it cannot connect). Xlib's
// macros (None, Status, Success) stay confined to this file.
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

// clang-format off
#include "lom/render/map_render.hpp"  // before Xlib: Eigen refuses Xlib's Success macro
#include <X11/Xlib.h>
// clang-format on

namespace lom::render {

namespace {

constexpr const char* kXvfbHint =
    "run it under a virtual X server, e.g. xvfb-run -a -s \"-screen 0 1280x1024x24\" "
    "labeloctomap render ...";

// An X server resets itself when its last client disconnects (Xvfb started by
// xvfb-run does), refusing connections for a moment. So the connection that
// found the display is kept open for the life of the process, which also keeps
// the server up for VTK's own connection; and a refused connection is retried
// for a short while in case another program's exit just triggered a reset.
Display* openDisplayOnce(const std::string& name) {
  static std::mutex mutex;
  static Display* display = nullptr;
  static std::string display_name;
  std::lock_guard<std::mutex> lock(mutex);
  if (display && display_name == name) return display;
  for (int attempt = 0; attempt < 20; ++attempt) {
    if (Display* opened = XOpenDisplay(name.c_str())) {
      display = opened;  // a previous connection to another name stays open: harmless
      display_name = name;
      return display;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return nullptr;
}

}  // namespace

bool canOpenDisplay(const std::string& name) { return openDisplayOnce(name) != nullptr; }

bool displayHasGlx(const std::string& name) {
  Display* display = openDisplayOnce(name);
  int opcode = 0, first_event = 0, first_error = 0;
  return display && XQueryExtension(display, "GLX", &opcode, &first_event, &first_error);
}

std::string missingGlxProblem(const std::string& who, const std::string& name) {
  return who + " needs OpenGL through the X server's GLX extension, which display '" + name +
         "' does not offer (ssh -X to a server that turns indirect GLX off, or a VNC server "
         "without it)";
}

std::optional<std::string> displayProblem() {
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name)
    return std::string("render needs an X server and DISPLAY is not set; ") + kXvfbHint;
  if (!canOpenDisplay(name))
    return std::string("render needs an X server and cannot open display '") + name + "'; " +
           kXvfbHint;
  // VTK aborts the process when it finds no OpenGL visual.
  if (!displayHasGlx(name)) return missingGlxProblem("render", name) + "; " + kXvfbHint;
  return std::nullopt;
}

}  // namespace lom::render
