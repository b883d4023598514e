#include "slice_image_writer.h"

#include <opencv2/imgcodecs.hpp>

#include "error.h"
#include "output_file.h"

namespace mvox {

void write_slice_image(const std::string& path, const SliceView& slice) {
  if (slice.type != SampleType::u8 && slice.type != SampleType::u16)
    throw Error(path, std::string("cannot write ") + sample_type_name(slice.type) +
                          " samples as an image (only 8- and 16-bit)");
  const int cv_type = slice.type == SampleType::u8 ? CV_8UC1 : CV_16UC1;
  // OpenCV only reads the pixels; the const_cast is how its Mat wraps external memory.
  const cv::Mat image(static_cast<int>(slice.height), static_cast<int>(slice.width), cv_type,
                      const_cast<void*>(slice.samples), slice.row_stride_bytes);
  const std::size_t dot = path.rfind('.');
  const std::string extension = dot == std::string::npos ? "" : path.substr(dot);
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
  OutputFile file(path);
  file.write(encoded.data(), encoded.size());
  file.commit();
}

}  // namespace mvox
