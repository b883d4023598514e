#include "write/slice_image_writer.h"

#include <sys/stat.h>

#include <cctype>

#include "error.h"
#include "modules/image_codecs.h"
#include "write/output_file.h"
#include "write/png_encoder.h"
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

bool is_png(const std::string& extension) {
  std::string lower = extension;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == ".png";
}

}  // namespace

void initialize_image_codecs(const std::string& path) {
  // No extension: check_image_extension refuses the name, OpenCV has nothing to say about it.
  const std::string extension = extension_of(path);
  if (!extension.empty() && !is_png(extension)) load_image_codecs(path);
}

void check_image_extension(const std::string& path) {
  const std::string extension = extension_of(path);
  // PNG is mvox's own; OpenCV (its module) is asked about any other type.
  const bool ok = is_png(extension) || (!extension.empty() && opencv_can_write(path, extension));
  if (!ok)
    throw Error(
        path, extension.empty()
                  ? "no image type: name the file .png, .pgm, .tif, .bmp or .jpg"
                  : "cannot write '" + extension + "' images: use .png, .pgm, .tif, .bmp or .jpg");
}

void write_slice_image(const std::string& path, const SliceView& slice) {
  write_image_file(path, encode_slice_image(path, slice));
}

void write_image_file(const std::string& path, const std::vector<unsigned char>& encoded) {
  OutputFile file(path);
  file.write(encoded.data(), encoded.size());
  file.commit();
}

std::vector<unsigned char> encode_slice_image(const std::string& path, const SliceView& slice) {
  if (slice.type != SampleType::u8 && slice.type != SampleType::u16)
    throw Error(path, std::string("cannot write ") + sample_type_name(slice.type) +
                          " samples as an image (only 8- and 16-bit)");
  const std::string extension = extension_of(path);
  if (is_png(extension)) {
    try {
      return encode_png(slice);
    } catch (const Error& e) {
      throw Error(path, e.problem());
    }
  }
  return encode_image_with_opencv(path, extension, slice);
}

}  // namespace mvox
