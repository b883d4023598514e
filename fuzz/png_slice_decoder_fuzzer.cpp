// Fuzzes the grey PNG slice decoder (src/read/image_stack/png_slice_decoder.h): mvox's own
// inflating and unfiltering of regular 8- and 16-bit files (png_plain_decoder.h), and libpng
// for everything else.
//
// Input: the bytes of a PNG file, checked as it is and again with every chunk's CRC made right.
// Properties: whatever the plain decoder reads, libpng reads too, to the same size, type and
// samples (it must never accept a file libpng refuses, nor read one differently); and the
// decoder either refuses in one printable line naming the file, or asks exactly once for the
// slice and fills it.

#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <vector>

#include "error.h"
#include "fuzz_check.h"
#include "read/image_stack/png_bytes.h"
#include "read/image_stack/png_plain_decoder.h"
#include "read/image_stack/png_slice_decoder.h"

namespace {

constexpr std::uint64_t kLimitBytes = std::uint64_t{64} << 20;

struct Slice {
  int calls = 0;
  std::uint32_t width = 0, height = 0;
  mvox::SampleType type = mvox::SampleType::f32;
  std::vector<unsigned char> samples;
};

mvox::PngDestination into(Slice& slice) {
  return [&slice](std::uint32_t width, std::uint32_t height, mvox::SampleType type) {
    ++slice.calls;
    slice.width = width;
    slice.height = height;
    slice.type = type;
    // Past 64 MiB a decoder must turn the failure into its one line, as for a machine without
    // the memory; and libFuzzer's RSS limit stays out of the way.
    const std::uint64_t bytes = std::uint64_t{width} * height * mvox::sample_bytes(type);
    if (bytes > kLimitBytes) throw std::bad_alloc();
    slice.samples.assign(bytes, 0xa5);
    return slice.samples.data();
  };
}

// Every chunk's CRC made right, so that mutations inside chunks reach the decoders instead of
// stopping at the CRC check.
std::vector<std::uint8_t> with_crcs_made_right(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> out(data, data + size);
  std::size_t at = 8;
  while (at + 12 <= out.size()) {
    const std::size_t length = mvox::png_uint32(out.data() + at);
    if (length > out.size() - at - 12) break;
    const std::uint32_t crc = mvox::png_crc(out.data() + at + 4, 4 + length);
    for (int i = 0; i < 4; ++i)
      out[at + 8 + length + i] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
    at += length + 12;
  }
  return out;
}

// The properties for one file.
void check(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "fuzzed.png";
  if (!mvox::is_plain_grey_png(data, size)) return;  // the decoder's precondition
  // libpng allocates rows of the declared width before it asks for the slice. mvox sizes a
  // stack's slices from the first header, within its memory budget, before decoding; here
  // slices past the fuzzer's limit are skipped, as the destination below refuses them.
  const std::uint64_t width = mvox::png_uint32(data + 16);
  const std::uint64_t height = mvox::png_uint32(data + 20);
  if (width * height * 2 > kLimitBytes || width * 16 > kLimitBytes) return;

  Slice plain;
  bool plain_read = false;
  try {
    plain_read = mvox::decode_plain_grey_png(data, size, into(plain));
  } catch (const std::bad_alloc&) {
    return;  // a slice past the fuzzer's limit
  }
  Slice libpng;
  std::string refusal;
  try {
    mvox::decode_png_with_libpng(path, data, size, into(libpng));
  } catch (const mvox::Error& error) {
    refusal = error.what();
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(error.what()), error.what());
    MVOX_FUZZ_CHECK(error.subject() == path, error.what());
  } catch (const std::bad_alloc&) {
    // A slice past the fuzzer's limit, which the plain decoder did not ask for: it left the
    // file to libpng before its header's size mattered.
    MVOX_FUZZ_CHECK(!plain_read, "libpng asked for a slice past the limit, the plain decoder not");
    return;
  }
  if (plain_read) {
    MVOX_FUZZ_CHECK(refusal.empty(), "read by the plain decoder, refused by libpng: " + refusal);
    MVOX_FUZZ_CHECK(plain.calls == 1 && libpng.calls == 1, "the slice asked for more than once");
    MVOX_FUZZ_CHECK(
        plain.width == libpng.width && plain.height == libpng.height && plain.type == libpng.type,
        "the plain decoder and libpng give different sizes or types");
    MVOX_FUZZ_CHECK(plain.samples == libpng.samples,
                    "the plain decoder and libpng give different samples");
  }

  Slice both;
  try {
    mvox::decode_png_slice(path, data, size, into(both));
  } catch (const mvox::Error& error) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(error.what()), error.what());
    MVOX_FUZZ_CHECK(both.calls <= 1, "the slice was asked for more than once");
    return;
  } catch (const std::bad_alloc&) {
    MVOX_FUZZ_CHECK(both.calls == 1, "a refused slice asked for more than once");
    return;
  }
  MVOX_FUZZ_CHECK(both.calls == 1, "a decoded slice was never asked for");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check(data, size);
  const std::vector<std::uint8_t> repaired = with_crcs_made_right(data, size);
  check(repaired.data(), repaired.size());
  return 0;
}
