// LiveWindow: the reasons it gives when there is no window to be had, and a real window on a
// private X server (Xvfb) when one can be started. gtest_discover_tests runs every test in its
// own process, so changing DISPLAY here touches no other test.
#include "picture/live_window.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "picture/display_probe.h"

namespace mvox {
namespace {

// The first executable called `name` on PATH, or "" if there is none.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string candidate = dirs.substr(start, end - start) + "/" + name;
    if (end > start && access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return "";
}

// An X server of our own, on a display number it picks itself (-displayfd), so that tests run
// in parallel never race for one. Killed, and waited for, when the object goes away; and by
// the kernel if this process dies first (PR_SET_PDEATHSIG), so that none is ever left behind.
class Xvfb {
 public:
  Xvfb() {
    const std::string program = find_on_path("Xvfb");
    if (program.empty()) {
      why_not_ = "Xvfb is not installed (apt-get install xvfb)";
      return;
    }
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
      why_not_ = "pipe failed";
      return;
    }
    // Everything the child needs is made before fork: after it, in a process that may have
    // threads (Qt's), only async-signal-safe calls are allowed.
    const std::string fd_text = std::to_string(fds[1]);
    std::vector<std::string> args = {program, "-displayfd", fd_text,     "-screen",
                                     "0",     "320x240x24", "-nolisten", "tcp"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGTERM);     // TERM: Xvfb then removes its socket and lock
      if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
      fcntl(fds[1], F_SETFD, 0);            // the write end is Xvfb's, across exec
      // Xvfb warns about /tmp/.X11-unix ownership and keyboard maps on every start.
      const int null_fd = open("/dev/null", O_WRONLY);
      dup2(null_fd, STDOUT_FILENO);
      dup2(null_fd, STDERR_FILENO);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(fds[1]);
    if (pid_ < 0) {
      close(fds[0]);
      why_not_ = "fork failed";
      return;
    }
    // Xvfb writes the display number and a newline once it accepts clients.
    std::string number;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (number.empty() || number.back() != '\n') {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      pollfd p{fds[0], POLLIN, 0};
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
      char c;
      if (read(fds[0], &c, 1) != 1) break;
      number += c;
    }
    close(fds[0]);
    if (number.size() < 2 || number.back() != '\n') {
      why_not_ = "Xvfb did not report a display within 2 s";
      return;
    }
    number.pop_back();
    display_ = ":" + number;
  }

  ~Xvfb() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    for (int i = 0; i < 100; ++i) {  // 1 s for a clean exit, which removes its socket and lock
      if (waitpid(pid_, nullptr, WNOHANG) == pid_) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }

  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;

  // ":N" once the server is up, else empty and why_not() says why.
  const std::string& display() const { return display_; }
  const std::string& why_not() const { return why_not_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
  std::string why_not_;
};

// One server for the whole test process, stopped when the process exits. Qt connects to the
// display once and keeps that connection until the process ends, ending the process itself
// when the server goes away, so the server must outlive every test that opens a window.
const Xvfb& shared_xvfb() {
  static const Xvfb server;
  return server;
}

bool module_built() {
#ifdef MVOX_HAVE_LIVE_WINDOW
  return true;
#else
  return false;
#endif
}

// The map state xwininfo reports for the window titled `title` on `display` ("IsViewable",
// "IsUnMapped"), or "" when there is no such window.
std::string map_state(const std::string& display, const std::string& title) {
  const std::string command = "xwininfo -display " + display + " -name '" + title + "' 2>/dev/null";
  std::string text;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, n);
    pclose(pipe);
  }
  const std::string key = "Map State: ";
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return "";
  const std::size_t start = at + key.size();
  return text.substr(start, text.find('\n', start) - start);
}

bool have_xwininfo() { return std::system("command -v xwininfo >/dev/null 2>&1") == 0; }

// An image whose value rises to the right and, less steeply, downwards (0 to 220 at 64x48):
// asymmetric, so a swapped width and height would show a different picture.
std::vector<std::uint8_t> gradient(std::uint32_t width, std::uint32_t height) {
  std::vector<std::uint8_t> pixels(width * height);
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) pixels[y * width + x] = x * 2 + y * 2;
  return pixels;
}

// A display server of the test's own that listens and then, to each connection, replies with
// eight bytes, closes it, or says nothing (the kernel completes a connection in the listening
// backlog without accept(), so a silent server needs no thread).
class FakeDisplay {
 public:
  enum class Reply { bytes, close, none };

  // Listens on `address`, of `bytes` bytes (AF_UNIX or AF_INET).
  FakeDisplay(const sockaddr* address, socklen_t bytes, Reply reply) {
    fd_ = ::socket(address->sa_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0 || ::bind(fd_, address, bytes) != 0 || ::listen(fd_, 8) != 0) {
      ADD_FAILURE() << "cannot listen: " << std::strerror(errno);
      return;
    }
    if (reply == Reply::none) return;
    server_ = std::thread([this, reply] {
      const int client = ::accept(fd_, nullptr, nullptr);
      if (client < 0) return;  // shut down before any client came
      char request[64];
      if (reply == Reply::bytes && ::read(client, request, sizeof request) > 0) {
        const char answer[8] = {1, 0, 11, 0, 0, 0, 0, 0};
        if (::write(client, answer, sizeof answer) != sizeof answer) {
        }
        char rest;
        if (::read(client, &rest, 1) < 0) {  // until the client hangs up
        }
      }
      ::close(client);
    });
  }
  ~FakeDisplay() {
    if (fd_ >= 0) ::shutdown(fd_, SHUT_RDWR);  // wakes accept()
    if (server_.joinable()) server_.join();
    if (fd_ >= 0) ::close(fd_);
  }
  FakeDisplay(const FakeDisplay&) = delete;
  FakeDisplay& operator=(const FakeDisplay&) = delete;

  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  std::thread server_;
};

// An X display number no server uses, for an abstract socket of the test's own.
int free_display_number() { return 50000 + static_cast<int>(getpid() % 9000); }

sockaddr_un x_abstract_address(int number, socklen_t* bytes) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string path = "/tmp/.X11-unix/X" + std::to_string(number);
  std::memcpy(address.sun_path + 1, path.data(), path.size());
  *bytes = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + 1 + path.size());
  return address;
}

void use_x_display(const std::string& display) {
  setenv("DISPLAY", display.c_str(), 1);
  unsetenv("WAYLAND_DISPLAY");
  unsetenv("QT_QPA_PLATFORM");
}

constexpr std::chrono::milliseconds kShortWait{300};

TEST(DisplayProbe, AnXServerThatRepliesAnswersOneThatStaysSilentOrHangsUpDoesNot) {
  const int number = free_display_number();
  socklen_t bytes = 0;
  const sockaddr_un address = x_abstract_address(number, &bytes);
  const std::string display = ":" + std::to_string(number);
  use_x_display(display);
  {
    FakeDisplay server(reinterpret_cast<const sockaddr*>(&address), bytes,
                       FakeDisplay::Reply::bytes);
    EXPECT_EQ(display_problem(kShortWait * 10), "");
  }
  {
    FakeDisplay server(reinterpret_cast<const sockaddr*>(&address), bytes,
                       FakeDisplay::Reply::none);
    EXPECT_EQ(display_problem(kShortWait), "the X display \"" + display +
                                               "\" accepted a connection but did not answer within "
                                               "0.3 s");
  }
  {
    FakeDisplay server(reinterpret_cast<const sockaddr*>(&address), bytes,
                       FakeDisplay::Reply::close);
    EXPECT_EQ(display_problem(kShortWait * 10),
              "the X display \"" + display + "\" closed the connection without answering");
  }
  EXPECT_EQ(display_problem(kShortWait), "cannot connect to the X display \"" + display + "\"");
}

TEST(DisplayProbe, ASilentXServerOverTcpDoesNotAnswer) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  FakeDisplay server(reinterpret_cast<const sockaddr*>(&address), sizeof address,
                     FakeDisplay::Reply::none);
  socklen_t bytes = sizeof address;
  ASSERT_EQ(getsockname(server.fd(), reinterpret_cast<sockaddr*>(&address), &bytes), 0);
  const int port = ntohs(address.sin_port);
  if (port <= 6000) GTEST_SKIP() << "port " << port << " is no X display's (6000 + N)";
  const std::string display = "127.0.0.1:" + std::to_string(port - 6000) + ".0";
  use_x_display(display);
  EXPECT_EQ(display_problem(kShortWait), "the X display \"" + display +
                                             "\" accepted a connection but did not answer "
                                             "within 0.3 s");
}

TEST(DisplayProbe, WaylandIsAskedWhenQtIsToldToUseIt) {
  char directory[] = "/tmp/mvox_wayland_XXXXXX";
  ASSERT_NE(mkdtemp(directory), nullptr);
  setenv("XDG_RUNTIME_DIR", directory, 1);
  setenv("WAYLAND_DISPLAY", "wayland-test", 1);
  setenv("QT_QPA_PLATFORM", "wayland", 1);
  unsetenv("DISPLAY");
  const std::string path = std::string(directory) + "/wayland-test";
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const auto bytes = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + path.size() + 1);
  EXPECT_EQ(display_problem(kShortWait), "cannot connect to the Wayland display \"" + path + "\"");
  for (const FakeDisplay::Reply reply : {FakeDisplay::Reply::bytes, FakeDisplay::Reply::none}) {
    {
      FakeDisplay server(reinterpret_cast<const sockaddr*>(&address), bytes, reply);
      EXPECT_EQ(display_problem(kShortWait),
                reply == FakeDisplay::Reply::bytes
                    ? ""
                    : "the Wayland display \"" + path +
                          "\" accepted a connection but did not answer within 0.3 s");
    }
    unlink(path.c_str());
  }
  unsetenv("XDG_RUNTIME_DIR");
  EXPECT_EQ(display_problem(kShortWait),
            "the Wayland display \"wayland-test\" lies in XDG_RUNTIME_DIR, which is not set");
  rmdir(directory);
  unsetenv("QT_QPA_PLATFORM");
  unsetenv("WAYLAND_DISPLAY");
}

TEST(LiveWindow, WithoutAnyDisplayOpenReturnsNullAndSaysSo) {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  std::string why = "untouched";
  EXPECT_EQ(LiveWindow::open("mvox test", &why), nullptr);
  EXPECT_EQ(why, "no display: neither DISPLAY nor WAYLAND_DISPLAY is set");
  EXPECT_EQ(LiveWindow::open("mvox test", nullptr), nullptr);  // a null why_not is allowed
}

#ifndef MVOX_HAVE_LIVE_WINDOW
TEST(LiveWindow, WithADisplayButNoModuleSaysMvoxWasBuiltWithoutHighgui) {
  setenv("DISPLAY", ":0", 1);
  std::string why;
  EXPECT_EQ(LiveWindow::open("mvox test", &why), nullptr);
  EXPECT_EQ(why, "mvox was built without OpenCV highgui");
}
#endif

// A DISPLAY left over from a closed session: Qt would end the process trying to reach it, so
// the module must refuse first, and the test process must still be alive to check that.
TEST(LiveWindow, DisplayWithNoServerIsRefusedNotFatal) {
  if (!module_built()) GTEST_SKIP() << "mvox was built without OpenCV highgui";
  setenv("DISPLAY", ":59123", 1);  // no server listens on display 59123
  unsetenv("WAYLAND_DISPLAY");
  std::string why;
  EXPECT_EQ(LiveWindow::open("mvox test", &why), nullptr);
  EXPECT_EQ(why, "cannot connect to the X display \":59123\"");
  setenv("DISPLAY", "localhost:59123.0", 1);  // the TCP form ssh -X sets
  EXPECT_EQ(LiveWindow::open("mvox test", &why), nullptr);
  EXPECT_EQ(why, "cannot connect to the X display \"localhost:59123.0\"");

  // Wayland alone: Qt would try X anyway, and end the process, unless told to use Wayland.
  unsetenv("DISPLAY");
  unsetenv("QT_QPA_PLATFORM");
  setenv("WAYLAND_DISPLAY", "wayland-59123", 1);
  EXPECT_EQ(LiveWindow::open("mvox test", &why), nullptr);
  EXPECT_EQ(why.rfind("OpenCV's window needs an X display and DISPLAY is not set", 0), 0u) << why;
}

TEST(LiveWindow, ShowsAGradientOnXvfb) {
  if (!module_built()) GTEST_SKIP() << "mvox was built without OpenCV highgui";
  const Xvfb& server = shared_xvfb();
  if (server.display().empty()) GTEST_SKIP() << server.why_not();
  setenv("DISPLAY", server.display().c_str(), 1);
  unsetenv("WAYLAND_DISPLAY");

  std::string why;
  {
    std::unique_ptr<LiveWindow> window = LiveWindow::open("mvox live window test", &why);
    ASSERT_NE(window, nullptr) << why;
    // Loaded from where MVOX_MODULE_PATH says the build put it (module_loader.h), as ctest
    // sets it for the host tests.
    const char* modules = std::getenv("MVOX_MODULE_PATH");
    ASSERT_NE(modules, nullptr) << "ctest sets MVOX_MODULE_PATH for the host tests";
    EXPECT_EQ(LiveWindow::module_path(), std::string(modules) + "/libmvox_live_window.so");

    std::string second_why;
    EXPECT_EQ(LiveWindow::open("second", &second_why), nullptr);
    EXPECT_EQ(second_why, "a live window is already open");

    const std::vector<std::uint8_t> image = gradient(64, 48);
    window->show(image.data(), 64, 48);
    EXPECT_EQ(window->error(), "");
    EXPECT_EQ(window->frames_shown(), 1u);
    // Within kMinUpdateInterval of the first: skipped, until forced.
    for (int i = 0; i < 5; ++i) window->show(image.data(), 64, 48);
    EXPECT_EQ(window->frames_shown(), 1u);
    window->show(image.data(), 64, 48, /*force=*/true);
    EXPECT_EQ(window->frames_shown(), 2u);
    EXPECT_EQ(window->error(), "");

    if (have_xwininfo())
      EXPECT_EQ(map_state(server.display(), "mvox live window test"), "IsViewable");
  }
  if (have_xwininfo())  // Qt keeps a closed window's X window, unmapped
    EXPECT_NE(map_state(server.display(), "mvox live window test"), "IsViewable");
  // Closed, so a new window can be opened in the same process.
  std::unique_ptr<LiveWindow> again = LiveWindow::open("mvox live window again", &why);
  ASSERT_NE(again, nullptr) << why;
  const std::vector<std::uint8_t> image = gradient(64, 48);
  again->show(image.data(), 64, 48, /*force=*/true);
  EXPECT_EQ(again->error(), "");
  if (have_xwininfo())
    EXPECT_EQ(map_state(server.display(), "mvox live window again"), "IsViewable");
}

}  // namespace
}  // namespace mvox
