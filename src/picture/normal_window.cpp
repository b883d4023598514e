#include "picture/normal_window.h"

#include <algorithm>
#include <cmath>

#include "error.h"

namespace mvox {

namespace {

// `spacing` scaled by a power of two that brings its largest value into [1, 2). A normal's
// direction depends only on the ratios of the spacings, but VertexNormals divides the density
// differences by them in float and squares the result: a spacing of 1e-37 made gradients of
// 1e39, infinite, and one of 1e36 gradients whose squares were 0, and either way every normal
// fell back to its axis. A power of two changes no bit of the ratios, so ordinary spacings give
// exactly the normals they gave before.
glm::vec3 normal_spacing(const std::array<double, 3>& spacing) {
  const double largest = std::max({spacing[0], spacing[1], spacing[2]});
  const int exponent = largest > 0.0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
  return glm::vec3(static_cast<float>(std::ldexp(spacing[0], -exponent)),
                   static_cast<float>(std::ldexp(spacing[1], -exponent)),
                   static_cast<float>(std::ldexp(spacing[2], -exponent)));
}

}  // namespace

NormalWindow::NormalWindow(const VolumeInfo& volume, const std::array<double, 3>& spacing,
                           const std::string& input_label, std::uint32_t depth)
    : depth_(depth), normals_(window_, normal_spacing(spacing)) {
  const std::size_t bytes = slice_window_bytes(volume.width, volume.height, volume.type, depth);
  if (bytes == 0) throw Error(input_label, "slices too large to keep for normals");
  memory_.resize(bytes);
  const Status status = window_.init(memory_.data(), memory_.size(), volume.width, volume.height,
                                     volume.type, depth);
  if (status != Status::ok)
    throw Error(input_label,
                std::string("cannot keep slices for normals: ") + status_message(status));
}

void NormalWindow::restart_for(SampleType type) {
  const Status status = window_.init(memory_.data(), memory_.size(), window_.width(),
                                     window_.height(), type, depth_);
  if (status != Status::ok)
    throw Error("normals", std::string("cannot keep slices: ") + status_message(status));
}

}  // namespace mvox
