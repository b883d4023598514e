// libmvox_live_window.so: the C interface of live_window_module.h over OpenCV's imshow.
#include "live_window_module.h"

#include <cstdio>
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
