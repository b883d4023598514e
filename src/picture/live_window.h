#pragma once
// A preview window for `mvox extract --show`, shown through an optional module so that mvox
// itself never links OpenCV's highgui (and, through it, Qt).
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

namespace mvox {

// A window that shows 8-bit grey images, for watching slices go by during an extraction.
//
// The window lives in libmvox_live_window.so, loaded with dlopen on the first open() from where
// mvox's modules are (modules/module_loader.h). Once loaded it stays loaded until the process
// ends.
//
// At most one LiveWindow exists at a time. Call open(), show() and the destructor from one
// thread: the toolkit's windows belong to the thread that created the first one.
// Nothing here throws; a failed window must never stop the extraction it only shows.
class LiveWindow {
 public:
  // Opens a window titled `title` (UTF-8), owned by the caller. Returns nullptr, and writes a
  // one-line reason without a final period to `*why_not` unless it is null, when:
  //   - there is no display: neither DISPLAY nor WAYLAND_DISPLAY is set;
  //   - mvox was built without OpenCV highgui (the module does not exist);
  //   - the module cannot be loaded (for instance highgui is not installed where mvox runs);
  //   - the display does not answer within kDisplayAnswerTimeout (display_probe.h): no server
  //     there, or one that accepts the connection and stays silent;
  //   - the window cannot be opened;
  //   - another LiveWindow is still open.
  static std::unique_ptr<LiveWindow> open(const std::string& title, std::string* why_not);

  ~LiveWindow();  // closes the window
  LiveWindow(const LiveWindow&) = delete;
  LiveWindow& operator=(const LiveWindow&) = delete;

  // The shortest time between two updates that show() allows unless forced: a window repaints
  // far more slowly than the engine makes slices, and must not set the pace of the extraction.
  static constexpr std::chrono::milliseconds kMinUpdateInterval{50};  // 20 updates a second

  // Shows `width` x `height` 8-bit grey pixels, rows packed with no padding. `pixels` is only read
  // during the call. Skipped, returning at once, when the last update was less than
  // kMinUpdateInterval ago, unless `force` is true (use it for the final image, so the window
  // ends on what was really last). After the first failure every call does nothing; see error().
  void show(const std::uint8_t* pixels, std::uint32_t width, std::uint32_t height,
            bool force = false);

  // Images actually handed to the window (not skipped by the throttle).
  std::uint64_t frames_shown() const { return frames_shown_; }

  // Empty while the window works; otherwise a one-line reason why it stopped updating.
  const std::string& error() const { return error_; }

  // The file the window module was loaded from; empty until an open() has loaded it.
  static std::string module_path();

 private:
  LiveWindow() = default;

  std::uint64_t frames_shown_ = 0;
  std::chrono::steady_clock::time_point last_update_;
  std::string error_;
};

}  // namespace mvox
