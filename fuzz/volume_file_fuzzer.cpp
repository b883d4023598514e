// Fuzzes whole NRRD, MetaImage and NIfTI files, header and data, through the readers behind
// `mvox extract` (src/read/nrrd/nrrd_file.h, src/read/metaimage/metaimage_file.h,
// src/read/nifti/nifti_file.h, src/read/stored_volume_source.h).
//
// Input: one byte choosing the format (modulo 4: 0 NRRD, 1 MetaImage, 2 NIfTI .nii, 3 NIfTI
// .nii.gz), then the file. Properties:
// a file is refused with one printable line, or it streams exactly the declared slices; and
// what it costs stays in proportion to its bytes: the reader's working memory never exceeds
// what the file's bytes can decode to at deflate's largest ratio (compression_bounds.h). Run
// with -malloc_limit_mb (scripts/fuzz.sh does), a header that drives a large allocation is a
// finding even where no property check sees it.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "error.h"
#include "fuzz_check.h"
#include "memory_file.h"
#include "read/compression_bounds.h"
#include "read/metaimage/metaimage_file.h"
#include "read/nifti/nifti_file.h"
#include "read/nrrd/nrrd_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int format = data[0] % 4;
  const std::string& path = mvox::fuzz::memory_file_with(data + 1, size - 1);
  try {
    std::unique_ptr<mvox::StoredVolumeSource> source =
        format == 0   ? mvox::open_nrrd_volume(path)
        : format == 1 ? mvox::open_metaimage_volume(path)
                      : mvox::open_nifti_file(path, format == 3);
    const mvox::VolumeInfo& info = source->info();
    const std::uint64_t slice =
        std::uint64_t{info.width} * info.height * mvox::sample_bytes(info.type);
    // Widened signed bytes take two bytes a sample, so twice deflate's ratio bounds a slice;
    // NIfTI's scaled bytes become floats, four bytes a sample.
    const std::uint64_t widening = format >= 2 ? 4 : 2;
    MVOX_FUZZ_CHECK(
        mvox::could_decode_to(size, widening * mvox::kDeflateMaxRatio, slice),
        "a slice of " + std::to_string(slice) + " bytes from a file of " + std::to_string(size));
    mvox::SliceView view;
    std::uint32_t slices = 0;
    while (source->next_slice(&view)) {
      MVOX_FUZZ_CHECK(view.width == info.width && view.height == info.height, "slice size");
      ++slices;
    }
    MVOX_FUZZ_CHECK(slices == info.depth, "slice count");
  } catch (const mvox::Error& error) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(error.what()), error.what());
  }
  return 0;
}
