// The image codecs module: OpenCV's imgcodecs behind image_codecs_api.h. Built as
// libmvox_image_codecs.so and loaded only by runs that need a format mvox does not decode or
// encode itself.
#include <climits>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "modules/image_codecs/image_codecs_api.h"

namespace {

void set_error(char* error, size_t error_bytes, const std::string& text) {
  if (error == nullptr || error_bytes == 0) return;
  std::snprintf(error, error_bytes, "%s", text.c_str());
}

int depth_code(int cv_depth) {
  switch (cv_depth) {
    case CV_8U: return MVOX_IMAGE_U8;
    case CV_8S: return MVOX_IMAGE_S8;
    case CV_16U: return MVOX_IMAGE_U16;
    case CV_16S: return MVOX_IMAGE_S16;
    case CV_32S: return MVOX_IMAGE_S32;
    case CV_32F: return MVOX_IMAGE_F32;
    case CV_64F: return MVOX_IMAGE_F64;
    default: return MVOX_IMAGE_OTHER;
  }
}

// The reason in an OpenCV error text "... error: (-2:Unspecified error) REASON in function
// 'f'", or "" when the text has no such part; one line whatever the decoder wrote.
std::string opencv_reason(const std::string& text) {
  const std::size_t code = text.find("error: (");
  if (code == std::string::npos) return "";
  const std::size_t start = text.find(") ", code);
  if (start == std::string::npos) return "";
  std::size_t end = text.find(" in function", start);
  if (end == std::string::npos) end = text.find('\n', start);
  std::string reason = text.substr(start + 2, end == std::string::npos ? end : end - start - 2);
  for (char& c : reason)
    if (c == '\n' || c == '\r') c = ' ';
  return reason;
}

// std::cerr's buffer is the process's: decodes that redirect it take turns, or one would put
// back another's buffer after it is gone (Python may decode on several threads at once).
std::mutex g_cerr_mutex;

// Puts std::cerr back on every way out.
struct CerrRedirect {
  explicit CerrRedirect(std::streambuf* into) : saved(std::cerr.rdbuf(into)) {}
  ~CerrRedirect() { std::cerr.rdbuf(saved); }
  std::streambuf* saved;
};

}  // namespace

extern "C" {

int mvox_image_codecs_api_version(void) { return MVOX_IMAGE_CODECS_API_VERSION; }

void mvox_image_codecs_initialize(void) {
  try {
    cv::haveImageWriter("image.png");
  } catch (...) {
    // Only the registration matters here; a real decode reports its own errors.
  }
}

int mvox_image_decode(const unsigned char* bytes, size_t size, mvox_image_destination destination,
                      void* context, char* error, size_t error_bytes) {
  try {
    if (size > static_cast<size_t>(INT_MAX)) {
      set_error(error, error_bytes, "image file is over 2 GiB, more than OpenCV decodes");
      return -1;
    }
    // OpenCV reports a decoder's failure on std::cerr ("imdecode_(''): can't read data: ..."),
    // a line of its own; mvox gives the reason in its one error line instead. mvox itself never
    // writes to std::cerr (its messages use stdio), so capturing it here hides nothing of ours.
    std::stringbuf decoder_messages;
    cv::Mat image;
    {
      const std::lock_guard<std::mutex> lock(g_cerr_mutex);
      const CerrRedirect redirect(&decoder_messages);
      try {
        // ANYDEPTH keeps 16-bit samples (the default would scale them to 8 bits); ANYCOLOR
        // keeps the channel count so that colour images are detected instead of silently
        // converted. The Mat wraps the bytes without copying them.
        const cv::Mat encoded(1, static_cast<int>(size), CV_8UC1,
                              const_cast<unsigned char*>(bytes));
        if (size > 0) image = cv::imdecode(encoded, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
      } catch (const cv::Exception& e) {
        set_error(error, error_bytes, "cannot decode image: " + e.msg);
        return -1;
      }
    }
    if (image.empty()) {
      const std::string reason = opencv_reason(decoder_messages.str());
      set_error(error, error_bytes,
                reason.empty()
                    ? "cannot read image (unreadable, corrupt, truncated or not an image format)"
                    : "cannot decode image: " + reason);
      return -1;
    }
    const mvox_image_shape shape{image.cols, image.rows, image.channels(),
                                 depth_code(image.depth())};
    unsigned char* target = destination(context, &shape);
    if (target == nullptr) return 1;
    // Row by row: a decoded Mat may pad its rows.
    const size_t row_bytes = static_cast<size_t>(image.cols) * image.elemSize();
    for (int y = 0; y < image.rows; ++y)
      std::memcpy(target + static_cast<size_t>(y) * row_bytes, image.ptr(y), row_bytes);
    return 0;
  } catch (const std::bad_alloc&) {
    set_error(error, error_bytes, "out of memory while OpenCV decoded the image");
  } catch (...) {
    set_error(error, error_bytes, "cannot decode image: OpenCV failed");
  }
  return -1;
}

int mvox_image_can_write(const char* extension) {
  try {
    return extension != nullptr && extension[0] != '\0' &&
                   cv::haveImageWriter(std::string("image") + extension)
               ? 1
               : 0;
  } catch (...) {
    return 0;
  }
}

int mvox_image_encode(const char* extension, const void* samples, int width, int height,
                      size_t row_stride_bytes, int bits, mvox_image_sink sink, void* context) {
  try {
    if (bits != 8 && bits != 16) return -1;
    // OpenCV only reads the pixels; the const_cast is how its Mat wraps external memory.
    const cv::Mat image(height, width, bits == 8 ? CV_8UC1 : CV_16UC1, const_cast<void*>(samples),
                        row_stride_bytes);
    std::vector<unsigned char> encoded;
    if (!cv::imencode(extension, image, encoded)) return -1;
    return sink(context, encoded.data(), encoded.size()) == 0 ? 0 : -1;
  } catch (...) {
    return -1;
  }
}

}  // extern "C"
