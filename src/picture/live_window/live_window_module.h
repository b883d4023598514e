#pragma once
// The C interface between mvox and its live window module, libmvox_live_window.so.
// The module is the only code that links OpenCV's highgui, and through it Qt; mvox loads it with
// dlopen for --show alone, so runs without a window never load Qt. C, not C++, because nothing
// may cross a dlopen boundary that two builds could lay out differently, exceptions included.
// Call every function from one thread (Qt's GUI thread is the one that first opened a window).
#include <stddef.h>

#if defined(__GNUC__)
#define MVOX_LIVE_WINDOW_EXPORT __attribute__((visibility("default")))
#else
#define MVOX_LIVE_WINDOW_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

// Bumped whenever a signature or a contract below changes, so that mvox refuses a stale module
// found on the library search path instead of calling it with the wrong arguments.
#define MVOX_LIVE_WINDOW_API_VERSION 2

// Returns MVOX_LIVE_WINDOW_API_VERSION as the module was built.
MVOX_LIVE_WINDOW_EXPORT int mvox_live_window_api_version(void);

// Opens the one window, titled `title` (UTF-8). The caller must have checked that the display
// answers (mvox's display_probe.h; since version 2 the module does not): Qt ends the process on
// a display it cannot reach. Returns 0 on success. On failure returns -1 and
// writes a one-line reason without a final period into `error` (`error_bytes` long, always
// terminated; `error` may be null when `error_bytes` is 0). Opening while a window is open
// closes that one first.
MVOX_LIVE_WINDOW_EXPORT int mvox_live_window_open(const char* title, char* error,
                                                  size_t error_bytes);

// Shows an 8-bit grey image, `width` x `height` pixels, rows packed with no padding, and lets
// the window process its events for about a millisecond. `gray` is read before the call returns
// and may then be reused. Returns 0 on success, -1 when no window is open or the toolkit failed.
MVOX_LIVE_WINDOW_EXPORT int mvox_live_window_show(const unsigned char* gray, int width, int height);

// Closes the window if one is open. Safe to call at any time.
MVOX_LIVE_WINDOW_EXPORT void mvox_live_window_close(void);

#ifdef __cplusplus
}
#endif
