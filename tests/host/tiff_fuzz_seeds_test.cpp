// The TIFF fuzzer's seeds (fuzz/corpus/tiff_stack_fuzzer/): a small stack of every layout the
// reader's tests write (striped, one row a strip with deflate, tiled, tiled with LZW), in 8 and
// 16 bits, plus deflate with the horizontal and floating-point predictors, a big-endian BigTIFF
// and a big-endian file whose bits are stored least significant first (mvox's own directory
// reading and byte and bit orders), and a stack of 40 small pages. MVOX_WRITE_FUZZ_SEEDS=DIR writes
// them into DIR; the test checks that each committed seed still reads as the samples it was made
// of.
#include <tiffio.h>

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "gtest/gtest.h"
#include "tiff_stack_files.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::tiff_stack_files::Layout;
using test::tiff_stack_files::read_stack;
using test::tiff_stack_files::write_stack;

constexpr std::uint32_t kSeedWidth = 21, kSeedHeight = 18, kSeedDepth = 2;

// Writes the seed `name` holding the phantom's samples of type T into `dir`, and checks the
// committed copy of it reads back as those samples.
template <typename T>
void check_seed(const std::string& name, const Layout& layout,
                const std::function<void(TIFF*)>& extra = {}, const char* mode = "w",
                std::uint32_t width = kSeedWidth, std::uint32_t height = kSeedHeight,
                std::uint32_t depth = kSeedDepth) {
  SCOPED_TRACE(name);
  const std::vector<T> samples = test::phantom_samples<T>(width, height, depth);
  if (const char* write_to = std::getenv("MVOX_WRITE_FUZZ_SEEDS")) {
    write_stack((fs::path(write_to) / name).string(), samples, width, height, 0, depth, layout,
                extra, mode);
  }
  const fs::path committed = fs::path(MVOX_FUZZ_CORPUS) / "tiff_stack_fuzzer" / name;
  ASSERT_TRUE(fs::exists(committed)) << committed << " is missing";
  EXPECT_EQ(read_stack<T>({committed.string()}), samples);
}

TEST(TiffFuzzSeeds, EveryCommittedSeedReadsAsTheSamplesItWasMadeOf) {
  for (const Layout& layout : test::tiff_stack_files::kLayouts) {
    std::string name;  // "tiled 16x16, LZW" -> "tiled_16x16_LZW"
    for (const char c : std::string(layout.name)) {
      if (std::isalnum(static_cast<unsigned char>(c)))
        name += c;
      else if (name.back() != '_')
        name += '_';
    }
    check_seed<std::uint8_t>("u8_" + name + ".tif", layout);
    check_seed<std::uint16_t>("u16_" + name + ".tif", layout);
  }
  const Layout deflate{"striped, deflate", false, 6, COMPRESSION_ADOBE_DEFLATE};
  check_seed<std::int16_t>("i16_deflate_predictor.tif", deflate, [](TIFF* tiff) {
    TIFFSetField(tiff, TIFFTAG_PREDICTOR, PREDICTOR_HORIZONTAL);
  });
  check_seed<float>("f32_deflate_float_predictor.tif", deflate, [](TIFF* tiff) {
    TIFFSetField(tiff, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT);
  });
  check_seed<std::uint16_t>("u16_bigtiff_big_endian_tiled.tif", test::tiff_stack_files::kLayouts[2],
                            {}, "w8b");
  check_seed<std::uint16_t>(
      "u16_big_endian_fill_order_2.tif", test::tiff_stack_files::kLayouts[0],
      [](TIFF* tiff) { TIFFSetField(tiff, TIFFTAG_FILLORDER, FILLORDER_LSB2MSB); }, "wb");
  // 40 small pages: the fuzzer's second range starts past page 16, from a marked directory.
  check_seed<std::uint8_t>("u8_40_small_pages.tif", test::tiff_stack_files::kLayouts[0], {}, "w", 6,
                           5, 40);
}

}  // namespace
}  // namespace mvox
