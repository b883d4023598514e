#include "normal_window.h"

#include "error.h"

namespace mvox {

NormalWindow::NormalWindow(const VolumeInfo& volume, const std::array<double, 3>& spacing,
                           const std::string& input_label)
    : normals_(window_, glm::vec3(static_cast<float>(spacing[0]), static_cast<float>(spacing[1]),
                                  static_cast<float>(spacing[2]))) {
  const std::size_t bytes = slice_window_bytes(volume.width, volume.height, volume.type);
  if (bytes == 0) throw Error(input_label, "slices too large to keep for normals");
  memory_.resize(bytes);
  const Status status =
      window_.init(memory_.data(), memory_.size(), volume.width, volume.height, volume.type);
  if (status != Status::ok)
    throw Error(input_label,
                std::string("cannot keep slices for normals: ") + status_message(status));
}

}  // namespace mvox
