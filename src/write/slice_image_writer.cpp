#include "write/slice_image_writer.h"

#include <sys/stat.h>

#include <opencv2/imgcodecs.hpp>

#include "error.h"
#include "write/output_file.h"
#include "write/standard_descriptors.h"

namespace mvox {

namespace {

// The image type to write: the extension, or PNG for standard output and the descriptors,
// devices and pipes that have no extension to go by (as mesh outputs get PLY).
std::string extension_of(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  const std::size_t slash = path.rfind('/');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash))
    return path.substr(dot);
  struct stat status {};
  const bool special =
      ::stat(path.c_str(), &status) == 0 && !S_ISREG(status.st_mode) && !S_ISDIR(status.st_mode);
  return path == "-" || descriptor_named_by(path) || special ? ".png" : "";
}

}  // namespace

void initialize_image_codecs() {
  try {
    cv::haveImageWriter("image.png");
  } catch (const cv::Exception&) {
    // Only the registration matters here; a real encoder reports its own errors.
  }
}

void check_image_extension(const std::string& path) {
  const std::string extension = extension_of(path);
  bool ok = false;
  try {
    ok = !extension.empty() && cv::haveImageWriter("image" + extension);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok)
    throw Error(
        path, extension.empty()
                  ? "no image type: name the file .png, .pgm, .tif, .bmp or .jpg"
                  : "cannot write '" + extension + "' images: use .png, .pgm, .tif, .bmp or .jpg");
}

void write_slice_image(const std::string& path, const SliceView& slice) {
  const std::vector<unsigned char> encoded = encode_slice_image(path, slice);
  OutputFile file(path);
  file.write(encoded.data(), encoded.size());
  file.commit();
}

std::vector<unsigned char> encode_slice_image(const std::string& path, const SliceView& slice) {
  if (slice.type != SampleType::u8 && slice.type != SampleType::u16)
    throw Error(path, std::string("cannot write ") + sample_type_name(slice.type) +
                          " samples as an image (only 8- and 16-bit)");
  const int cv_type = slice.type == SampleType::u8 ? CV_8UC1 : CV_16UC1;
  // OpenCV only reads the pixels; the const_cast is how its Mat wraps external memory.
  const cv::Mat image(static_cast<int>(slice.height), static_cast<int>(slice.width), cv_type,
                      const_cast<void*>(slice.samples), slice.row_stride_bytes);
  const std::string extension = extension_of(path);
  std::vector<unsigned char> encoded;
  bool ok = false;
  try {
    ok = cv::imencode(extension, image, encoded);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok)
    throw Error(path, "cannot encode a " + std::string(sample_type_name(slice.type)) +
                          " image with extension '" + extension + "'");
  return encoded;
}

}  // namespace mvox
