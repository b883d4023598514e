#include "picture/live_window.h"

#include <dlfcn.h>
#include <limits.h>

#include <cstdlib>

#include "modules/module_loader.h"
#include "picture/display_probe.h"
#include "picture/live_window/live_window_module.h"

namespace mvox {
namespace {

// The module's entry points, resolved once and kept for the life of the process. We never
// dlclose it: Qt starts threads and registers exit handlers from inside it, and unloading the
// code they point into crashes the process later.
struct Module {
  decltype(&mvox_live_window_open) open = nullptr;
  decltype(&mvox_live_window_show) show = nullptr;
  decltype(&mvox_live_window_close) close = nullptr;
  std::string path;
};
Module g_module;
bool g_window_open = false;

bool has_display() {
  for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY"}) {
    const char* value = std::getenv(name);
    if (value != nullptr && value[0] != '\0') return true;
  }
  return false;
}

#ifdef MVOX_HAVE_LIVE_WINDOW

constexpr const char* kModuleName = "libmvox_live_window.so";
constexpr ModuleName kLiveWindow{kModuleName, "live window module (OpenCV highgui)",
                                 "OpenCV's highgui (apt-get install libopencv-highgui-dev)"};

// Loads the module and resolves its functions, or says why not.
bool load_module(std::string* why_not) {
  if (g_module.open != nullptr) return true;
  void* handle = mvox::load_module(kLiveWindow, "mvox_live_window_api_version",
                                   MVOX_LIVE_WINDOW_API_VERSION, why_not);
  if (handle == nullptr) return false;
  Module module;
  module.open =
      reinterpret_cast<decltype(module.open)>(module_symbol(handle, "mvox_live_window_open"));
  module.show =
      reinterpret_cast<decltype(module.show)>(module_symbol(handle, "mvox_live_window_show"));
  module.close =
      reinterpret_cast<decltype(module.close)>(module_symbol(handle, "mvox_live_window_close"));
  if (module.open == nullptr || module.show == nullptr || module.close == nullptr) {
    *why_not = std::string("the live window module lacks its functions: ") + kModuleName;
    return false;
  }
  // Where the dynamic loader really found it.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(module.open), &info) != 0 && info.dli_fname != nullptr)
    module.path = info.dli_fname;
  else
    module.path = kModuleName;
  g_module = module;
  return true;
}

#endif  // MVOX_HAVE_LIVE_WINDOW

}  // namespace

std::unique_ptr<LiveWindow> LiveWindow::open(const std::string& title, std::string* why_not) {
  std::string reason;
  if (!has_display()) {
    reason = "no display: neither DISPLAY nor WAYLAND_DISPLAY is set";
  } else if (g_window_open) {
    reason = "a live window is already open";
  } else {
#ifdef MVOX_HAVE_LIVE_WINDOW
    // The display is asked first, with a time limit: Qt, inside the module, would end the
    // process on a display it cannot reach and wait for ever on one that never replies.
    reason = display_problem();
    if (reason.empty() && load_module(&reason)) {
      char error[512] = "";
      if (g_module.open(title.c_str(), error, sizeof error) == 0) {
        g_window_open = true;
        return std::unique_ptr<LiveWindow>(new LiveWindow());
      }
      reason = error[0] != '\0' ? error : "cannot open a window";
    }
#else
    (void)title;
    reason = "mvox was built without OpenCV highgui";
#endif
  }
  if (why_not != nullptr) *why_not = reason;
  return nullptr;
}

LiveWindow::~LiveWindow() {
  if (g_module.close != nullptr) g_module.close();
  g_window_open = false;
}

void LiveWindow::show(const std::uint8_t* pixels, std::uint32_t width, std::uint32_t height,
                      bool force) {
  if (!error_.empty()) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && frames_shown_ > 0 && now - last_update_ < kMinUpdateInterval) return;
  if (width > INT_MAX || height > INT_MAX) {
    error_ = "image too large for the live window: " + std::to_string(width) + "x" +
             std::to_string(height);
    return;
  }
  if (g_module.show(pixels, static_cast<int>(width), static_cast<int>(height)) != 0) {
    error_ = "the live window failed to show an image";
    return;
  }
  ++frames_shown_;
  // Timed from the end of the update, so that a slow repaint lengthens the pause after it and
  // the window's share of the time stays bounded.
  last_update_ = std::chrono::steady_clock::now();
}

std::string LiveWindow::module_path() { return g_module.path; }

}  // namespace mvox
