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
#include <GL/glx.h>
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

namespace {

// X errors while probing are answers, not reasons to exit (Xlib's default
// handler ends the process).
bool probe_failed = false;
int noteProbeError(Display* /*display*/, XErrorEvent* /*error*/) {
  probe_failed = true;
  return 0;
}

}  // namespace

bool displayHasGlx(const std::string& name) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  Display* display = openDisplayOnce(name);
  int error_base = 0, event_base = 0;
  if (!display || !glXQueryExtension(display, &error_base, &event_base)) return false;
  // The extension alone is not enough: a server that turns indirect GLX off
  // (as Xorg does by default, reached over ssh -X) has it but gives no
  // context. So a context is made, as VTK and Qt will make theirs.
  int attributes[] = {GLX_RGBA,
                      GLX_DOUBLEBUFFER,
                      GLX_RED_SIZE,
                      1,
                      GLX_GREEN_SIZE,
                      1,
                      GLX_BLUE_SIZE,
                      1,
                      GLX_DEPTH_SIZE,
                      1,
                      None};
  XVisualInfo* visual = glXChooseVisual(display, DefaultScreen(display), attributes);
  if (!visual) return false;
  XSync(display, False);
  probe_failed = false;
  const auto previous = XSetErrorHandler(noteProbeError);
  const GLXContext context = glXCreateContext(display, visual, nullptr, True);
  XSync(display, False);
  // An indirect context (ssh -X, LIBGL_ALWAYS_INDIRECT on a server that
  // allows it) stops at OpenGL 1.4: VTK needs 3.2 and fails on it.
  const bool made = context && !probe_failed && glXIsDirect(display, context);
  if (context) glXDestroyContext(display, context);
  XSync(display, False);
  XSetErrorHandler(previous);
  XFree(visual);
  return made;
}

std::string missingGlxProblem(const std::string& who, const std::string& name) {
  return who + " needs OpenGL through the X server's GLX extension, and display '" + name +
         "' gives no OpenGL context drawn on this machine (no GLX extension, as on some VNC "
         "servers, or only indirect GLX, as over ssh -X, which stops at OpenGL 1.4)";
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
