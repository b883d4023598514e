// Makes a large test volume from a small one: a raw u8 volume resampled by trilinear
// interpolation to any size, one output slice at a time (two input slices in memory), so that
// end-to-end and writer benchmarks run on realistic data of 1024^3 voxels and more.
//   mvox_bench_resample IN.raw WxHxD OUT.raw W2xH2xD2
// For example the paper's engine (256x256x128) at 1024^3: a 1 GiB volume whose surface is the
// engine's, smooth and large (about 9 million polygons at threshold 100).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <vector>

namespace {

bool parse_size(const char* text, std::uint32_t size[3]) {
  return std::sscanf(text, "%ux%ux%u", &size[0], &size[1], &size[2]) == 3 && size[0] > 0 &&
         size[1] > 0 && size[2] > 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint32_t in_size[3], out_size[3];
  if (argc != 5 || !parse_size(argv[2], in_size) || !parse_size(argv[4], out_size)) {
    std::fprintf(stderr, "usage: %s IN.raw WxHxD OUT.raw W2xH2xD2 (u8 volumes)\n", argv[0]);
    return 2;
  }
  const std::size_t in_slice = std::size_t{in_size[0]} * in_size[1];
  std::vector<std::uint8_t> in(in_slice * in_size[2]);
  std::ifstream input(argv[1], std::ios::binary);
  if (!input.read(reinterpret_cast<char*>(in.data()), static_cast<std::streamsize>(in.size()))) {
    std::fprintf(stderr, "%s: cannot read %zu bytes\n", argv[1], in.size());
    return 1;
  }
  std::ofstream output(argv[3], std::ios::binary);
  std::vector<std::uint8_t> slice(std::size_t{out_size[0]} * out_size[1]);
  // Sample positions in input voxels: voxel centres map to voxel centres.
  auto source = [&](int axis, std::uint32_t i, std::uint32_t* low, float* weight) {
    const float x = (i + 0.5f) * in_size[axis] / out_size[axis] - 0.5f;
    const float clamped = std::fmin(std::fmax(x, 0.0f), in_size[axis] - 1.0f);
    *low = static_cast<std::uint32_t>(std::floor(clamped));
    if (*low + 1 >= in_size[axis]) *low = in_size[axis] > 1 ? in_size[axis] - 2 : 0;
    *weight = in_size[axis] > 1 ? clamped - *low : 0.0f;
  };
  for (std::uint32_t z = 0; z < out_size[2]; ++z) {
    std::uint32_t z0;
    float wz;
    source(2, z, &z0, &wz);
    const std::uint32_t z1 = in_size[2] > 1 ? z0 + 1 : z0;
    for (std::uint32_t y = 0; y < out_size[1]; ++y) {
      std::uint32_t y0;
      float wy;
      source(1, y, &y0, &wy);
      const std::uint32_t y1 = in_size[1] > 1 ? y0 + 1 : y0;
      for (std::uint32_t x = 0; x < out_size[0]; ++x) {
        std::uint32_t x0;
        float wx;
        source(0, x, &x0, &wx);
        const std::uint32_t x1 = in_size[0] > 1 ? x0 + 1 : x0;
        auto at = [&](std::uint32_t xi, std::uint32_t yi, std::uint32_t zi) {
          return static_cast<float>(in[zi * in_slice + std::size_t{yi} * in_size[0] + xi]);
        };
        const float c00 = at(x0, y0, z0) * (1 - wx) + at(x1, y0, z0) * wx;
        const float c10 = at(x0, y1, z0) * (1 - wx) + at(x1, y1, z0) * wx;
        const float c01 = at(x0, y0, z1) * (1 - wx) + at(x1, y0, z1) * wx;
        const float c11 = at(x0, y1, z1) * (1 - wx) + at(x1, y1, z1) * wx;
        const float v = (c00 * (1 - wy) + c10 * wy) * (1 - wz) + (c01 * (1 - wy) + c11 * wy) * wz;
        slice[std::size_t{y} * out_size[0] + x] = static_cast<std::uint8_t>(v + 0.5f);
      }
    }
    output.write(reinterpret_cast<const char*>(slice.data()),
                 static_cast<std::streamsize>(slice.size()));
  }
  if (!output) {
    std::fprintf(stderr, "%s: write failed\n", argv[3]);
    return 1;
  }
  return 0;
}
