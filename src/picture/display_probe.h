#pragma once
// Whether the display a --show window would open on answers, asked with a bounded wait.
// OpenCV's window toolkit on Debian (Qt) connects to the display itself, and ends the whole
// process when it cannot reach it; a server that accepts the connection but never replies makes
// it wait for ever. Either would take the extraction down with its preview, so mvox asks the
// display first, with a time limit, before loading the window module.
#include <chrono>
#include <string>

namespace mvox {

// How long display_problem() waits for the display's first reply.
inline constexpr std::chrono::seconds kDisplayAnswerTimeout{3};

// Empty when the display the window would use answers within `timeout`; otherwise a one-line
// reason without a final period. The display is chosen as Qt chooses it:
// - QT_QPA_PLATFORM naming wayland: the Wayland socket, WAYLAND_DISPLAY (default wayland-0)
//   under XDG_RUNTIME_DIR, or itself when it is an absolute path; asked with a wl_display.sync
//   request, to which a compositor replies with the callback's done event.
// - otherwise DISPLAY, "[protocol/][host]:number[.screen]": a local display through its socket
//   (Linux's abstract one first, then /tmp/.X11-unix/XN), a remote one over TCP port 6000 +
//   number; asked with the X11 connection setup request, to which a server replies (success,
//   failure or authenticate: any reply means it is there).
// - otherwise: why Qt would find no display (DISPLAY is not set).
// Connecting and waiting are bounded by `timeout` together; only a remote host's name lookup
// (getaddrinfo) is not.
std::string display_problem(std::chrono::milliseconds timeout = kDisplayAnswerTimeout);

}  // namespace mvox
