#include "read/raw/raw_input.h"

#include <filesystem>
#include <memory>
#include <system_error>

#include "error.h"
#include "read/input_format.h"
#include "read/raw/raw_slices_source.h"
#include "read/raw/raw_volume_source.h"

namespace mvox {
namespace {

OpenedInput open_volume(const InputRequest& request) {
  const RawFormat& raw = *request.options().raw;
  const std::string volume_text = "--raw " + raw_format_text(raw);
  const std::vector<std::string>& inputs = request.inputs();
  if (inputs.size() != 1)
    throw Error("INPUT", volume_text + " reads one volume file, got " +
                             std::to_string(inputs.size()) + " inputs");
  std::error_code error;
  if (std::filesystem::is_directory(inputs[0], error))
    throw Error(inputs[0], "is a directory; " + volume_text + " reads one volume file");
  OpenedInput opened;
  opened.files = request.files(InputKind::raw_files);
  if (opened.files.size() != 1)
    throw Error(inputs[0], "matches " + std::to_string(opened.files.size()) + " files; " +
                               volume_text + " reads one volume file");
  opened.source = std::make_unique<RawVolumeSource>(opened.files[0], raw);
  return opened;
}

OpenedInput open_slices(const InputRequest& request) {
  OpenedInput opened;
  opened.files = request.files(InputKind::raw_files);
  opened.source = std::make_unique<RawSlicesSource>(opened.files, *request.options().raw);
  return opened;
}

}  // namespace

const InputFormat& raw_volume_format() {
  static const InputFormat format{"raw volume",
                                  [](const InputRequest& request) {
                                    return request.options().raw &&
                                           request.options().raw->depth != 0;
                                  },
                                  open_volume};
  return format;
}

const InputFormat& raw_slices_format() {
  static const InputFormat format{"raw slices",
                                  [](const InputRequest& request) {
                                    return request.options().raw &&
                                           request.options().raw->depth == 0;
                                  },
                                  open_slices};
  return format;
}

}  // namespace mvox
