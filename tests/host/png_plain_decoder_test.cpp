// The plain PNG decoder (8- and 16-bit grey, not interlaced, inflated many rows at a time): the
// samples each of PNG's five filters encodes, in files built here chunk by chunk and in files
// libpng writes; and every irregular file it must leave to libpng, so that libpng keeps refusing
// or reading them as before.
#include "read/image_stack/png_plain_decoder.h"

#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "error.h"
#include "read/image_stack/png_slice_decoder.h"
#include "support/error_capture.h"
#include "support/file_io.h"
#include "support/libpng_writer.h"

namespace mvox {
namespace {

using Bytes = std::vector<unsigned char>;

struct Chunk {
  std::string type;
  Bytes data;
  bool damaged_crc = false;
};

void put_32(Bytes& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<unsigned char>(v >> shift));
}

Bytes file_of(const std::vector<Chunk>& chunks) {
  Bytes out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  for (const Chunk& chunk : chunks) {
    put_32(out, static_cast<std::uint32_t>(chunk.data.size()));
    const std::size_t type_at = out.size();
    out.insert(out.end(), chunk.type.begin(), chunk.type.end());
    out.insert(out.end(), chunk.data.begin(), chunk.data.end());
    const uLong crc = crc32(crc32(0, nullptr, 0), out.data() + type_at, 4 + chunk.data.size());
    put_32(out, static_cast<std::uint32_t>(crc) ^ (chunk.damaged_crc ? 1u : 0u));
  }
  return out;
}

Chunk ihdr(std::uint32_t width, std::uint32_t height, int bit_depth, int interlace = 0,
           int colour = 0, int compression = 0, int filter = 0) {
  Bytes data;
  put_32(data, width);
  put_32(data, height);
  for (int field : {bit_depth, colour, compression, filter, interlace})
    data.push_back(static_cast<unsigned char>(field));
  return {"IHDR", data};
}

// An image: `height` rows of `row_bytes` bytes as the file stores them (16-bit big-endian).
struct Image {
  std::uint32_t width, height;
  int bit_depth;
  Bytes rows;
  std::size_t bpp() const { return static_cast<std::size_t>(bit_depth / 8); }
  std::size_t row_bytes() const { return width * bpp(); }
};

Image random_image(std::uint32_t width, std::uint32_t height, int bit_depth, unsigned seed) {
  Image image{width, height, bit_depth, {}};
  std::mt19937 random(seed);
  image.rows.resize(image.row_bytes() * height);
  // Smooth runs and noise, so that every filter meets both carries and equal neighbours.
  for (std::size_t i = 0; i < image.rows.size(); ++i)
    image.rows[i] = static_cast<unsigned char>(i % 7 < 3 ? (i / 5) & 0xFF : random() & 0xFF);
  return image;
}

int paeth(int a, int b, int c) {
  const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// The filtered rows, row y filtered with filters[y % filters.size()], each after its filter byte.
Bytes filtered(const Image& image, const std::vector<int>& filters) {
  Bytes out;
  const std::size_t n = image.row_bytes(), bpp = image.bpp();
  const Bytes zeros(n, 0);
  for (std::uint32_t y = 0; y < image.height; ++y) {
    const unsigned char* x = image.rows.data() + y * n;
    const unsigned char* up = y == 0 ? zeros.data() : x - n;
    const int filter = filters[y % filters.size()];
    out.push_back(static_cast<unsigned char>(filter));
    for (std::size_t i = 0; i < n; ++i) {
      const int a = i >= bpp ? x[i - bpp] : 0, b = up[i], c = i >= bpp ? up[i - bpp] : 0;
      const int predicted = filter == 1   ? a
                            : filter == 2 ? b
                            : filter == 3 ? (a + b) / 2
                            : filter == 4 ? paeth(a, b, c)
                                          : 0;
      out.push_back(static_cast<unsigned char>(x[i] - predicted));
    }
  }
  return out;
}

Bytes compressed(const Bytes& data) {
  uLongf size = compressBound(data.size());
  Bytes out(size);
  EXPECT_EQ(compress2(out.data(), &size, data.data(), data.size(), 6), Z_OK);
  out.resize(size);
  return out;
}

// The image data as IDAT chunks of at most `part` bytes each.
std::vector<Chunk> idat_chunks(const Bytes& stream, std::size_t part) {
  std::vector<Chunk> chunks;
  for (std::size_t at = 0; at < stream.size(); at += part)
    chunks.push_back({"IDAT", Bytes(stream.begin() + static_cast<std::ptrdiff_t>(at),
                                    stream.begin() + static_cast<std::ptrdiff_t>(
                                                         std::min(stream.size(), at + part)))});
  return chunks;
}

Bytes png_of(const Image& image, const std::vector<Chunk>& before, const std::vector<Chunk>& idat,
             const std::vector<Chunk>& after) {
  std::vector<Chunk> chunks = {ihdr(image.width, image.height, image.bit_depth)};
  chunks.insert(chunks.end(), before.begin(), before.end());
  chunks.insert(chunks.end(), idat.begin(), idat.end());
  chunks.insert(chunks.end(), after.begin(), after.end());
  chunks.push_back({"IEND", {}});
  return file_of(chunks);
}

struct Decoded {
  bool decoded = false;
  int destinations = 0;  // calls of the destination
  std::uint32_t width = 0, height = 0;
  SampleType type = SampleType::f32;
  Bytes samples;
};

PngDestination into(Decoded& decoded) {
  return [&decoded](std::uint32_t width, std::uint32_t height, SampleType type) {
    ++decoded.destinations;
    decoded.width = width;
    decoded.height = height;
    decoded.type = type;
    decoded.samples.assign(std::size_t{width} * height * sample_bytes(type), 0xAB);
    return decoded.samples.data();
  };
}

Decoded plain(const Bytes& png, PngCrcs crcs = PngCrcs::check) {
  Decoded decoded;
  decoded.decoded = decode_plain_grey_png(png.data(), png.size(), into(decoded), crcs);
  return decoded;
}

// The image's samples as the decoder must give them: 16-bit in native byte order.
Bytes native_samples(const Image& image) {
  Bytes samples = image.rows;
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  if (image.bit_depth == 16 && first == 1)
    for (std::size_t i = 0; i + 1 < samples.size(); i += 2) std::swap(samples[i], samples[i + 1]);
  return samples;
}

TEST(PngPlainDecoder, EveryFilterGivesTheSamplesItEncodes) {
  const std::vector<std::vector<int>> filter_cycles = {{0}, {1}, {2}, {3}, {4}, {4, 3, 2, 1, 0}};
  for (int bit_depth : {8, 16}) {
    // Rows shorter and longer than zlib's fast path needs (258 bytes), and a batch of rows (64
    // KiB) split over more than one.
    for (const auto& [width, height] : {std::pair{1u, 1u}, std::pair{7u, 5u}, std::pair{33u, 17u},
                                        std::pair{300u, 9u}, std::pair{256u, 300u}}) {
      const Image image = random_image(width, height, bit_depth, width * 7 + height);
      for (const std::vector<int>& filters : filter_cycles) {
        SCOPED_TRACE(std::to_string(bit_depth) + "-bit " + std::to_string(width) + "x" +
                     std::to_string(height) + ", filter " + std::to_string(filters[0]) +
                     (filters.size() > 1 ? " and the others" : ""));
        const Bytes stream = compressed(filtered(image, filters));
        for (std::size_t part : {stream.size(), std::size_t{1}, std::size_t{100}}) {
          const Decoded decoded = plain(png_of(image, {}, idat_chunks(stream, part), {}));
          ASSERT_TRUE(decoded.decoded) << "IDAT chunks of " << part << " bytes";
          EXPECT_EQ(decoded.destinations, 1);
          EXPECT_EQ(decoded.width, width);
          EXPECT_EQ(decoded.height, height);
          EXPECT_EQ(decoded.type, bit_depth == 16 ? SampleType::u16 : SampleType::u8);
          EXPECT_TRUE(decoded.samples == native_samples(image));
        }
      }
    }
  }
}

// An empty IDAT chunk among the others, and rows wider than a batch (one row inflated at a time).
TEST(PngPlainDecoder, ReadsEmptyIdatChunksAndRowsWiderThanABatch) {
  const Image image = random_image(33, 17, 8, 12);
  const Bytes stream = compressed(filtered(image, {4, 3, 2, 1, 0}));
  std::vector<Chunk> idat = idat_chunks(stream, 50);
  idat.insert(idat.begin() + 1,
              Chunk{"IDAT", {}});  // (one after the stream's end is left to libpng)
  Decoded decoded = plain(png_of(image, {}, idat, {}));
  ASSERT_TRUE(decoded.decoded);
  EXPECT_TRUE(decoded.samples == native_samples(image));
  for (const auto& [width, bit_depth] : {std::pair{70000u, 8}, std::pair{40000u, 16}}) {
    const Image wide = random_image(width, 3, bit_depth, width);
    decoded = plain(png_of(wide, {}, {{"IDAT", compressed(filtered(wide, {1, 4, 3}))}}, {}));
    ASSERT_TRUE(decoded.decoded) << width << " wide, " << bit_depth << "-bit";
    EXPECT_TRUE(decoded.samples == native_samples(wide)) << width << " wide, " << bit_depth;
  }
}

// Image stacks check every chunk's CRC before decoding (image_file_check.h) and tell the decoder
// so; told nothing, it checks IHDR's, IDAT's and IEND's itself.
TEST(PngPlainDecoder, ChecksCrcsUnlessTheCallerHas) {
  const Image image = random_image(40, 9, 8, 5);
  const Bytes stream = compressed(filtered(image, {1, 2, 4}));
  for (const int damaged : {0, 1, 2}) {  // IHDR, the second IDAT, IEND
    std::vector<Chunk> chunks = {ihdr(image.width, image.height, image.bit_depth)};
    for (const Chunk& idat : idat_chunks(stream, 100)) chunks.push_back(idat);
    chunks.push_back({"IEND", {}});
    (damaged == 0 ? chunks[0] : damaged == 1 ? chunks[2] : chunks.back()).damaged_crc = true;
    const Bytes png = file_of(chunks);
    SCOPED_TRACE("damaged CRC of chunk kind " + std::to_string(damaged));
    EXPECT_FALSE(plain(png).decoded);
    const Decoded trusted = plain(png, PngCrcs::checked_already);
    ASSERT_TRUE(trusted.decoded);
    EXPECT_TRUE(trusted.samples == native_samples(image));
  }
}

// Written by libpng with its adaptive filters, text and gamma chunks before and after the image
// data, and IDAT chunks of 256 bytes: the decoder reads what libpng writes, as libpng reads it.
Bytes libpng_file(const Image& image) {
  return test::png_written_by_libpng([&](png_structp png, png_infop info) {
    png_set_compression_buffer_size(png, 256);
    png_set_IHDR(png, info, image.width, image.height, image.bit_depth, PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_gAMA(png, info, 0.45455);
    png_text text{};
    text.compression = PNG_TEXT_COMPRESSION_NONE;
    text.key = const_cast<char*>("Comment");
    text.text = const_cast<char*>("slice");
    png_set_text(png, info, &text, 1);
    png_write_info(png, info);
    for (std::uint32_t y = 0; y < image.height; ++y)
      png_write_row(png, image.rows.data() + y * image.row_bytes());
    png_set_text(png, info, &text, 1);  // a second tEXt, after the image data
  });
}

TEST(PngPlainDecoder, ReadsWhatLibpngWrites) {
  for (int bit_depth : {8, 16}) {
    const Image image = random_image(256, 40, bit_depth, 3);
    const Bytes png = libpng_file(image);
    const Decoded decoded = plain(png);
    ASSERT_TRUE(decoded.decoded) << bit_depth << "-bit";
    EXPECT_TRUE(decoded.samples == native_samples(image)) << bit_depth << "-bit";
  }
}

// Each irregular file is left to libpng (the plain decoder returns false), and through
// decode_png_slice libpng then refuses it or reads it, as it did before the plain decoder.
TEST(PngPlainDecoder, LeavesEveryIrregularFileToLibpng) {
  const Image image = random_image(33, 17, 8, 11);
  const Bytes rows = filtered(image, {4, 1, 2, 3, 0});
  const Bytes stream = compressed(rows);
  const std::vector<Chunk> idat = idat_chunks(stream, 64);
  Bytes bad_filter = rows;
  bad_filter[2 * 34] = 5;  // row 2's filter byte
  Bytes extra = stream;
  const Bytes more = compressed(Bytes(10, 1));
  extra.insert(extra.end(), more.begin(), more.end());  // a second stream after the first
  const Bytes short_stream = compressed(Bytes(rows.begin(), rows.end() - 34));
  const Bytes long_stream = compressed([&] {
    Bytes longer = rows;
    longer.insert(longer.end(), 34, 0);  // an 18th row
    return longer;
  }());
  std::vector<Chunk> idat_bad_crc = idat;
  idat_bad_crc[1].damaged_crc = true;
  std::vector<Chunk> split = idat;
  split.insert(split.begin() + 1, Chunk{"tEXt", Bytes{'a', 0, 'b'}});
  Chunk header = ihdr(33, 17, 8);
  header.damaged_crc = true;

  // What libpng does with each: reads the image (with a warning at most), or refuses the file;
  // or, for layouts the plain decoder does not read, whatever it did before (checked by
  // png_slice_decoder_test.cpp against OpenCV).
  enum class Libpng { reads, refuses, not_checked };
  struct Case {
    const char* what;
    Bytes png;
    Libpng libpng;
  };
  const std::vector<Case> cases = {
      {"interlaced", file_of({ihdr(33, 17, 8, 1), {"IDAT", stream}, {"IEND", {}}}),
       Libpng::not_checked},
      {"4-bit grey", file_of({ihdr(33, 17, 4), {"IDAT", stream}, {"IEND", {}}}),
       Libpng::not_checked},
      {"a damaged IHDR CRC", file_of({header, {"IDAT", stream}, {"IEND", {}}}), Libpng::refuses},
      {"a damaged IDAT CRC", png_of(image, {}, idat_bad_crc, {}), Libpng::refuses},
      {"an undefined filter type", png_of(image, {}, {{"IDAT", compressed(bad_filter)}}, {}),
       Libpng::refuses},
      {"image data short of the image", png_of(image, {}, {{"IDAT", short_stream}}, {}),
       Libpng::refuses},
      {"image data past the image", png_of(image, {}, {{"IDAT", long_stream}}, {}), Libpng::reads},
      {"bytes after the zlib stream", png_of(image, {}, {{"IDAT", extra}}, {}), Libpng::reads},
      {"IDAT chunks apart", png_of(image, {}, split, {}), Libpng::refuses},
      {"a palette in a grey image", png_of(image, {{"PLTE", Bytes(3, 0)}}, idat, {}),
       Libpng::reads},
      {"an unknown critical chunk", png_of(image, {{"ABCD", Bytes(2, 0)}}, idat, {}),
       Libpng::refuses},
      {"no IEND",
       [&] {
         Bytes png = png_of(image, {}, idat, {});
         png.resize(png.size() - 12);
         return png;
       }(),
       Libpng::refuses},
      {"a chunk type that is not letters", png_of(image, {{"ab1d", Bytes(2, 0)}}, idat, {}),
       Libpng::refuses},
      {"a damaged IEND CRC",
       [&] {
         std::vector<Chunk> chunks = {ihdr(33, 17, 8)};
         chunks.insert(chunks.end(), idat.begin(), idat.end());
         chunks.push_back({"IEND", {}, true});
         return file_of(chunks);
       }(),
       Libpng::refuses},
      {"IEND with data",
       [&] {
         std::vector<Chunk> chunks = {ihdr(33, 17, 8)};
         chunks.insert(chunks.end(), idat.begin(), idat.end());
         chunks.push_back({"IEND", Bytes(1, 0)});
         return file_of(chunks);
       }(),
       Libpng::not_checked},
      {"an unknown critical chunk after the image data",
       png_of(image, {}, idat, {{"ABCD", Bytes(2, 0)}}), Libpng::refuses},
      {"colour (RGB)", file_of({ihdr(33, 17, 8, 0, 2), {"IDAT", stream}, {"IEND", {}}}),
       Libpng::not_checked},
      {"compression method 1", file_of({ihdr(33, 17, 8, 0, 0, 1), {"IDAT", stream}, {"IEND", {}}}),
       Libpng::refuses},
      {"filter method 1", file_of({ihdr(33, 17, 8, 0, 0, 0, 1), {"IDAT", stream}, {"IEND", {}}}),
       Libpng::refuses},
      {"image data one byte short",
       png_of(image, {}, {{"IDAT", compressed(Bytes(rows.begin(), rows.end() - 1))}}, {}),
       Libpng::refuses},
      {"image data one byte past the image",
       png_of(image, {}, {{"IDAT", compressed([&] {
                             Bytes longer = rows;
                             longer.push_back(0);
                             return longer;
                           }())}},
              {}),
       Libpng::reads},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_FALSE(plain(c.png).decoded);
    Decoded through_libpng;
    if (c.libpng == Libpng::reads) {
      decode_png_slice("s.png", c.png.data(), c.png.size(), into(through_libpng));
      EXPECT_EQ(through_libpng.destinations, 1);  // asked once though both decoders looked
      EXPECT_TRUE(through_libpng.samples == image.rows);
    } else if (c.libpng == Libpng::refuses) {
      EXPECT_CONTAINS(test::error_of([&] {
                        decode_png_slice("s.png", c.png.data(), c.png.size(), into(through_libpng));
                      }),
                      "s.png: cannot decode PNG: ");
      EXPECT_LE(through_libpng.destinations, 1);
    }
  }
}

// The fuzzer's seeds (fuzz/corpus/png_slice_decoder_fuzzer/): small files the plain decoder reads,
// and irregular ones it leaves to libpng. MVOX_WRITE_FUZZ_SEEDS=DIR writes them into DIR; the
// test checks what each committed seed gives.
TEST(PngPlainDecoder, FuzzSeeds) {
  namespace fs = std::filesystem;
  const Image small = random_image(9, 6, 8, 5);
  const Image deep = random_image(20, 6, 16, 6);
  const Bytes rows = filtered(small, {0, 1, 2, 3, 4});
  Bytes bad_filter = rows;
  bad_filter[10] = 7;  // row 1's filter byte
  struct Seed {
    std::string name;
    Bytes bytes;
    bool plain;  // the plain decoder reads it; otherwise libpng refuses it
    const Image* image;
  };
  const std::vector<Seed> seeds = {
      {"filters_8bit_9x6.png", png_of(small, {}, idat_chunks(compressed(rows), 16), {}), true,
       &small},
      {"libpng_16bit_20x6.png", libpng_file(deep), true, &deep},
      {"bad_filter_8bit_9x6.png", png_of(small, {}, {{"IDAT", compressed(bad_filter)}}, {}), false,
       nullptr},
  };
  for (const Seed& seed : seeds) {
    SCOPED_TRACE(seed.name);
    const Bytes bytes = test::committed_fuzz_seed(
        fs::path(MVOX_FUZZ_CORPUS) / "png_slice_decoder_fuzzer", seed.name, seed.bytes);
    ASSERT_FALSE(bytes.empty());
    const Decoded decoded = plain(bytes);
    EXPECT_EQ(decoded.decoded, seed.plain);
    if (seed.plain)
      EXPECT_TRUE(decoded.samples == native_samples(*seed.image));
    else
      EXPECT_CONTAINS(test::error_of([&] {
                        Decoded unused;
                        decode_png_slice("s.png", bytes.data(), bytes.size(), into(unused));
                      }),
                      "s.png: cannot decode PNG: ");
  }
}

}  // namespace
}  // namespace mvox
