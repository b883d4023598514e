// Fuzzes one TIFF file through the TIFF stack reader behind `mvox extract`
// (src/read/tiff/tiff_stack_source.h): mvox's own reading of every directory (classic and
// BigTIFF, both byte orders; read/tiff/tiff_directory.h) and its checks (page format, strip and
// tile sizes against the file and against what their codec can decode to, tile sizes against
// the image), uncompressed and deflate data with the deflate check and the predictor, and, for
// other codecs, the comparison with libtiff's reading of the directory and libtiff's decoding
// in the TIFF module. The module is found through MVOX_MODULE_PATH (scripts/fuzz.sh and the seeds'
// test set it to the build's src/).
//
// Input: the file. Properties: a file is refused with one printable line, or it streams exactly
// the declared slices, each of the declared size, and two ranges of it (open_range, as slab
// workers read it) give the same slices again. Run with -malloc_limit_mb (scripts/fuzz.sh
// does), a directory that drives a large allocation beyond what the reader declared in
// working_bytes() (and so beyond the memory budget's reach) is a finding even where no
// property check sees it. Seeds: small stacks of every layout the tests write
// (tests/host/tiff_fuzz_seeds_test writes them again with MVOX_WRITE_FUZZ_SEEDS=DIR).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "error.h"
#include "fuzz_check.h"
#include "memory_file.h"
#include "read/tiff/tiff_file.h"
#include "read/tiff/tiff_stack_source.h"

constexpr std::uint64_t kMemoryBudget = std::uint64_t{128} << 20;

// Without the module every input would be refused in the same line, and the run would pass
// having fuzzed nothing.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const std::string problem = mvox::load_tiff_module();
  MVOX_FUZZ_CHECK(problem.empty(), problem);
  return 0;
}

namespace {

// FNV-1a of a slice's rows: what the ranges must give again.
std::uint64_t slice_hash(const mvox::SliceView& view) {
  const std::size_t row_bytes = std::size_t{view.width} * mvox::sample_bytes(view.type);
  std::uint64_t hash = 1469598103934665603u;
  for (std::uint32_t y = 0; y < view.height; ++y) {
    const auto* row = static_cast<const unsigned char*>(view.samples) + y * view.row_stride_bytes;
    for (std::size_t i = 0; i < row_bytes; ++i) hash = (hash ^ row[i]) * 1099511628211u;
  }
  return hash;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = mvox::fuzz::memory_file_with(data, size);
  std::vector<std::uint64_t> hashes;
  std::unique_ptr<mvox::TiffStackSource> source;
  try {
    source = std::make_unique<mvox::TiffStackSource>(std::vector<std::string>{path});
    // Pages of codecs with no bound on their expansion (LZMA, Zstandard, ...) are left to the
    // memory budget, which `mvox extract` checks against working_bytes() before reading a
    // slice: as `--max-memory 128M` would, the fuzzer does not stream what it refuses.
    if (source->working_bytes() > kMemoryBudget) return 0;
    const mvox::VolumeInfo& info = source->info();
    mvox::SliceView view;
    while (source->next_slice(&view)) {
      MVOX_FUZZ_CHECK(view.width == info.width && view.height == info.height, "slice size");
      MVOX_FUZZ_CHECK(view.type == info.type, "slice type");
      hashes.push_back(slice_hash(view));
    }
    MVOX_FUZZ_CHECK(hashes.size() == info.depth, "slice count");
  } catch (const mvox::Error& error) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(error.what()), error.what());
    return 0;
  }
  // A stack that streamed whole streams the same in two ranges, as two slab workers read it
  // (the second starting inside the file, from the nearest marked directory).
  const std::uint32_t depth = static_cast<std::uint32_t>(hashes.size());
  const std::uint32_t middle = depth / 2;
  for (const auto& [first, end] : {std::pair{0u, middle}, std::pair{middle, depth}}) {
    if (first == end) continue;
    try {
      std::unique_ptr<mvox::SliceSource> range = source->open_range(first, end);
      mvox::SliceView view;
      std::uint32_t index = first;
      while (range->next_slice(&view)) {
        MVOX_FUZZ_CHECK(index < end, "a range read past its end");
        MVOX_FUZZ_CHECK(slice_hash(view) == hashes[index], "a range read another slice");
        ++index;
      }
      MVOX_FUZZ_CHECK(index == end, "a range ended early");
    } catch (const mvox::Error& error) {
      MVOX_FUZZ_CHECK(false,
                      std::string("a range refused what the whole stack read: ") + error.what());
    }
  }
  return 0;
}
