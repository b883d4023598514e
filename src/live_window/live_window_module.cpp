// libmvox_live_window.so: the C interface of live_window_module.h over OpenCV's imshow.
#include "live_window_module.h"

#include <netdb.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/highgui.hpp>
#include <string>

namespace {

// The title of the open window; empty when none is. OpenCV names windows by their title.
std::string g_title;

void write_error(char* error, size_t error_bytes, const std::string& text) {
  if (error == nullptr || error_bytes == 0) return;
  std::snprintf(error, error_bytes, "%s", text.c_str());
}

// OpenCV's messages span lines ("OpenCV(4.6.0) file:line: error: (-2:...) text in function
// 'f'\n"); the reason we hand on is one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
  return text;
}

bool connects(int family, const sockaddr* address, socklen_t address_bytes) {
  const int fd = socket(family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  const bool connected = connect(fd, address, address_bytes) == 0;
  close(fd);
  return connected;
}

bool unix_socket_connects(const std::string& path, bool abstract) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  // An abstract address starts with a NUL byte and is not a file.
  const std::size_t offset = abstract ? 1 : 0;
  if (offset + path.size() >= sizeof address.sun_path) return false;
  std::memcpy(address.sun_path + offset, path.data(), path.size());
  const auto bytes = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + offset + path.size() +
                                            (abstract ? 0 : 1));
  return connects(AF_UNIX, reinterpret_cast<const sockaddr*>(&address), bytes);
}

bool tcp_connects(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* addresses = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &addresses) != 0)
    return false;
  bool connected = false;
  for (const addrinfo* a = addresses; a != nullptr && !connected; a = a->ai_next)
    connected = connects(a->ai_family, a->ai_addr, a->ai_addrlen);
  freeaddrinfo(addresses);
  return connected;
}

// Whether an X server answers at `display` ("[protocol/][host]:number[.screen]"), tried the way
// Xlib and xcb do: a local display through its socket (abstract first, as Linux servers listen
// on both), a remote one over TCP port 6000 + number. Qt, OpenCV's window toolkit on Debian,
// ends the whole process when it cannot reach the display; that would take the extraction down
// with its preview, so we look before Qt does.
bool x_server_answers(std::string display) {
  const std::size_t slash = display.find('/');
  if (slash != std::string::npos) display.erase(0, slash + 1);
  const std::size_t colon = display.rfind(':');
  if (colon == std::string::npos) return false;
  const std::string host = display.substr(0, colon);
  char* end = nullptr;
  const long number = std::strtol(display.c_str() + colon + 1, &end, 10);
  if (end == display.c_str() + colon + 1 || number < 0 || number > 59535) return false;
  if (host.empty() || host == "unix") {
    const std::string path = "/tmp/.X11-unix/X" + std::to_string(number);
    return unix_socket_connects(path, true) || unix_socket_connects(path, false);
  }
  return tcp_connects(host, 6000 + static_cast<int>(number));
}

// Empty when OpenCV can be asked for a window, else why not.
std::string display_problem() {
  const char* display = std::getenv("DISPLAY");
  if (display != nullptr && display[0] != '\0') {
    if (!x_server_answers(display))
      return std::string("cannot connect to the X display \"") + display + "\"";
    return "";
  }
  // Without DISPLAY, Qt reaches Wayland only through its Wayland platform plugin, and only when
  // told to; if it is told to and the plugin is missing, that is the user's explicit choice.
  const char* platform = std::getenv("QT_QPA_PLATFORM");
  if (platform != nullptr && std::strstr(platform, "wayland") != nullptr) return "";
  return "OpenCV's window needs an X display and DISPLAY is not set (for Wayland alone, set "
         "QT_QPA_PLATFORM=wayland)";
}

void close_window() {
  if (g_title.empty()) return;
  const std::string title = g_title;
  g_title.clear();
  try {
    cv::destroyWindow(title);
    cv::waitKey(1);  // lets the toolkit act on the destruction now, not at the next event
  } catch (...) {
    // Nothing more to do for a window that cannot even be closed.
  }
}

}  // namespace

extern "C" {

int mvox_live_window_api_version(void) { return MVOX_LIVE_WINDOW_API_VERSION; }

int mvox_live_window_open(const char* title, char* error, size_t error_bytes) {
  close_window();
  const std::string problem = display_problem();
  if (!problem.empty()) {
    write_error(error, error_bytes, problem);
    return -1;
  }
  try {
    const std::string name = title != nullptr && title[0] != '\0' ? title : "mvox";
    // GUI_NORMAL: without it Qt adds a toolbar of text buttons some 1500 pixels wide, which
    // dwarfs a preview of small slices.
    cv::namedWindow(name, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
    g_title = name;
    return 0;
  } catch (const cv::Exception& e) {
    write_error(error, error_bytes, "cannot open a window: " + one_line(e.what()));
  } catch (const std::exception& e) {
    write_error(error, error_bytes, "cannot open a window: " + one_line(e.what()));
  } catch (...) {
    write_error(error, error_bytes, "cannot open a window: unknown error");
  }
  return -1;
}

int mvox_live_window_show(const unsigned char* gray, int width, int height) {
  if (g_title.empty() || gray == nullptr || width <= 0 || height <= 0) return -1;
  try {
    // cv::Mat wants a non-const pointer; imshow only reads (and copies) the pixels.
    const cv::Mat image(height, width, CV_8UC1, const_cast<unsigned char*>(gray));
    cv::imshow(g_title, image);
    cv::waitKey(1);  // without it the window never repaints
    return 0;
  } catch (...) {
    return -1;
  }
}

void mvox_live_window_close(void) { close_window(); }

}  // extern "C"
