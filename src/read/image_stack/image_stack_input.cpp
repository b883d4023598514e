#include "read/image_stack/image_stack_input.h"

#include <memory>

#include "error.h"
#include "read/image_stack/image_stack_source.h"
#include "read/input_format.h"
#include "read/tiff/tiff_stack_source.h"

namespace mvox {
namespace {

OpenedInput open(const InputRequest& request) {
  OpenedInput opened;
  opened.files = request.files(InputKind::image_stack);
  // OpenCV reads one page of a TIFF file: a stack among other images would lose the others.
  for (const std::string& file : opened.files) {
    if (!has_tiff_extension(file)) continue;
    const std::uint64_t pages = tiff_page_count(file);
    if (pages > 1)
      throw Error(file, "is a TIFF stack of " + std::to_string(pages) +
                            " pages among other images; give TIFF stacks without other image "
                            "types");
  }
  opened.source = std::make_unique<ImageStackSource>(opened.files);
  return opened;
}

}  // namespace

const InputFormat& image_stack_format() {
  static const InputFormat format{
      "image stack", [](const InputRequest& request) { return !request.options().raw; }, open};
  return format;
}

}  // namespace mvox
