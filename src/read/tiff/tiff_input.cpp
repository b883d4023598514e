#include "read/tiff/tiff_input.h"

#include <algorithm>
#include <memory>

#include "read/input_format.h"
#include "read/tiff/tiff_stack_source.h"

namespace mvox {
namespace {

bool claims(const InputRequest& request) {
  if (request.options().raw) return false;
  const std::vector<std::string>& files = request.files(InputKind::image_stack);
  return !files.empty() && std::all_of(files.begin(), files.end(), has_tiff_extension);
}

OpenedInput open(const InputRequest& request) {
  OpenedInput opened;
  opened.files = request.files(InputKind::image_stack);
  opened.source = std::make_unique<TiffStackSource>(opened.files);
  return opened;
}

}  // namespace

const InputFormat& tiff_stack_format() {
  static const InputFormat format{"TIFF stack", claims, open};
  return format;
}

}  // namespace mvox
