#include "picture/display_probe.h"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace mvox {
namespace {

using Clock = std::chrono::steady_clock;

int milliseconds_left(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? static_cast<int>(left) : 0;
}

// Waits for `events` on `fd` until `deadline`; false on timeout or error.
bool wait_for(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    pollfd ready{fd, events, 0};
    const int result = ::poll(&ready, 1, milliseconds_left(deadline));
    if (result > 0) return true;
    if (result == 0 || errno != EINTR) return false;
  }
}

enum class Answer { no_connection, answered, closed, silent };

// Connects to `address` without blocking past `deadline`, sends `request` and waits for the
// first byte of a reply.
Answer ask(int family, const sockaddr* address, socklen_t address_bytes,
           const std::vector<unsigned char>& request, Clock::time_point deadline) {
  const int fd = ::socket(family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return Answer::no_connection;
  Answer answer = Answer::no_connection;
  int error = 0;
  socklen_t error_bytes = sizeof error;
  const bool connected =
      ::connect(fd, address, address_bytes) == 0 ||
      ((errno == EINPROGRESS || errno == EAGAIN) && wait_for(fd, POLLOUT, deadline) &&
       ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &error_bytes) == 0 && error == 0);
  if (connected) {
    answer = Answer::silent;
    // A request this small goes into an empty socket buffer whole.
    const ssize_t sent = ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    if (sent == static_cast<ssize_t>(request.size()) && wait_for(fd, POLLIN, deadline)) {
      unsigned char byte = 0;
      const ssize_t got = ::recv(fd, &byte, 1, 0);
      // Nothing read although the socket was ready: the server hung up (end of file, or a
      // reset when it closed with our request unread).
      answer = got > 0 ? Answer::answered : Answer::closed;
    } else if (sent < 0) {
      answer = Answer::closed;
    }
  }
  ::close(fd);
  return answer;
}

// `path` as a Unix socket address; abstract (Linux: no file, the name after a NUL byte) or not.
bool unix_address(const std::string& path, bool abstract, sockaddr_un* address, socklen_t* bytes) {
  *address = sockaddr_un{};
  address->sun_family = AF_UNIX;
  const std::size_t offset = abstract ? 1 : 0;
  if (offset + path.size() >= sizeof address->sun_path) return false;
  std::memcpy(address->sun_path + offset, path.data(), path.size());
  *bytes = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + offset + path.size() +
                                  (abstract ? 0 : 1));
  return true;
}

std::string problem(const std::string& what, Answer answer, std::chrono::milliseconds timeout) {
  switch (answer) {
    case Answer::answered: return "";
    case Answer::no_connection: return "cannot connect to " + what;
    case Answer::closed: return what + " closed the connection without answering";
    case Answer::silent: break;
  }
  const auto seconds = std::chrono::duration<double>(timeout).count();
  char limit[32];
  std::snprintf(limit, sizeof limit, "%g s", seconds);
  return what + " accepted a connection but did not answer within " + limit;
}

// The X11 connection setup request, little-endian: byte order 'l', protocol 11.0, no
// authorization. Any server replies to it, if only to refuse.
const std::vector<unsigned char> kX11Setup = {'l', 0, 11, 0, 0, 0, 0, 0, 0, 0, 0, 0};

std::string x_display_problem(std::string display, std::chrono::milliseconds timeout) {
  const std::string what = "the X display \"" + display + "\"";
  const Clock::time_point deadline = Clock::now() + timeout;
  const std::size_t slash = display.find('/');
  if (slash != std::string::npos) display.erase(0, slash + 1);
  const std::size_t colon = display.rfind(':');
  if (colon == std::string::npos) return "cannot connect to " + what;
  const std::string host = display.substr(0, colon);
  char* end = nullptr;
  const long number = std::strtol(display.c_str() + colon + 1, &end, 10);
  if (end == display.c_str() + colon + 1 || number < 0 || number > 59535)
    return "cannot connect to " + what;
  if (host.empty() || host == "unix") {
    const std::string path = "/tmp/.X11-unix/X" + std::to_string(number);
    // As Xlib and xcb do: the abstract socket first (Linux servers listen on both), then the
    // file; the first that connects is the server.
    for (const bool abstract : {true, false}) {
      sockaddr_un address;
      socklen_t bytes = 0;
      if (!unix_address(path, abstract, &address, &bytes)) continue;
      const Answer answer =
          ask(AF_UNIX, reinterpret_cast<const sockaddr*>(&address), bytes, kX11Setup, deadline);
      if (answer != Answer::no_connection) return problem(what, answer, timeout);
    }
    return "cannot connect to " + what;
  }
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* addresses = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(6000 + number).c_str(), &hints, &addresses) != 0)
    return "cannot connect to " + what;
  Answer answer = Answer::no_connection;
  for (const addrinfo* a = addresses; a != nullptr && answer == Answer::no_connection;
       a = a->ai_next)
    answer = ask(a->ai_family, a->ai_addr, a->ai_addrlen, kX11Setup, deadline);
  ::freeaddrinfo(addresses);
  return problem(what, answer, timeout);
}

// wl_display.sync (object 1, opcode 0, 12 bytes, new callback id 2), in native byte order as
// the Wayland wire format has it; the compositor answers with wl_callback.done.
std::vector<unsigned char> wayland_sync() {
  const std::uint32_t words[3] = {1, (12u << 16) | 0u, 2};
  std::vector<unsigned char> bytes(sizeof words);
  std::memcpy(bytes.data(), words, sizeof words);
  return bytes;
}

std::string wayland_display_problem(std::chrono::milliseconds timeout) {
  const char* name = std::getenv("WAYLAND_DISPLAY");
  std::string path = name != nullptr && name[0] != '\0' ? name : "wayland-0";
  if (path[0] != '/') {
    const char* runtime = std::getenv("XDG_RUNTIME_DIR");
    if (runtime == nullptr || runtime[0] == '\0')
      return "the Wayland display \"" + path + "\" lies in XDG_RUNTIME_DIR, which is not set";
    path = std::string(runtime) + "/" + path;
  }
  const std::string what = "the Wayland display \"" + path + "\"";
  sockaddr_un address;
  socklen_t bytes = 0;
  if (!unix_address(path, false, &address, &bytes)) return "cannot connect to " + what;
  return problem(what,
                 ask(AF_UNIX, reinterpret_cast<const sockaddr*>(&address), bytes, wayland_sync(),
                     Clock::now() + timeout),
                 timeout);
}

}  // namespace

std::string display_problem(std::chrono::milliseconds timeout) {
  const char* platform = std::getenv("QT_QPA_PLATFORM");
  if (platform != nullptr && std::strstr(platform, "wayland") != nullptr)
    return wayland_display_problem(timeout);
  const char* display = std::getenv("DISPLAY");
  if (display != nullptr && display[0] != '\0') return x_display_problem(display, timeout);
  // Without DISPLAY, Qt reaches Wayland only through its Wayland platform plugin, and only when
  // told to.
  return "OpenCV's window needs an X display and DISPLAY is not set (for Wayland alone, set "
         "QT_QPA_PLATFORM=wayland)";
}

}  // namespace mvox
