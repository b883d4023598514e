// The --raw format (src/read/raw/raw_format.h): per-slice and volume specs parsed, malformed ones
// refused naming the option in one printable line, and byte swapping to the native order.
#include "read/raw/raw_format.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "error_capture.h"
#include "volume_samples.h"

namespace mvox {
namespace {

using test::encode_u16;
using test::error_of;

// Appends `value` as `byte_count` bytes in the given order, independent of the host's order.
void append(std::vector<unsigned char>& bytes, std::uint32_t value, int byte_count,
            ByteOrder order) {
  for (int i = 0; i < byte_count; ++i) {
    const int shift = order == ByteOrder::little ? 8 * i : 8 * (byte_count - 1 - i);
    bytes.push_back(static_cast<unsigned char>(value >> shift));
  }
}

TEST(RawFormat, ParsesPerSliceAndVolumeSpecs) {
  const RawFormat slices = parse_raw_format("256x256:u16be");
  EXPECT_EQ(slices.width, 256u);
  EXPECT_EQ(slices.height, 256u);
  EXPECT_EQ(slices.depth, 0u);
  EXPECT_EQ(slices.type, SampleType::u16);
  EXPECT_EQ(slices.byte_order, ByteOrder::big);
  EXPECT_EQ(slices.bytes_per_sample, 2u);
  EXPECT_EQ(slices.slice_bytes(), 131072u);

  const RawFormat volume = parse_raw_format("7x5x6:f32le");
  EXPECT_EQ(volume.width, 7u);
  EXPECT_EQ(volume.height, 5u);
  EXPECT_EQ(volume.depth, 6u);
  EXPECT_EQ(volume.type, SampleType::f32);
  EXPECT_EQ(volume.byte_order, ByteOrder::little);
  EXPECT_EQ(volume.bytes_per_sample, 4u);
  EXPECT_EQ(raw_format_text(volume), "7x5x6 f32le");

  EXPECT_EQ(parse_raw_format("3x2:u8").type, SampleType::u8);
  EXPECT_EQ(parse_raw_format("3x2:u16le").byte_order, ByteOrder::little);
  EXPECT_EQ(parse_raw_format("3x2:i16le").type, SampleType::i16);
  EXPECT_EQ(parse_raw_format("3x2:i16be").byte_order, ByteOrder::big);
  EXPECT_EQ(raw_format_text(parse_raw_format("3x2:i16be")), "3x2 i16be");
}

TEST(RawFormat, RejectsMalformedSpecsNamingTheOption) {
  const std::vector<std::string> bad = {"256x:u8",
                                        "0x5:u8",
                                        "4x4:u24",
                                        "4x4x4x4:u8",
                                        "",
                                        "4x4",
                                        "4x4:",
                                        "x4:u8",
                                        ":u8",
                                        "4x4:u8:u8",
                                        "-4x4:u8",
                                        "4x4x0:u8",
                                        "4 x4:u8",
                                        "4x4:U8",
                                        "4x4:u16",
                                        "4.5x4:u8",
                                        "0x0x0:u8",
                                        "4x4x:u8",
                                        "4294967296x1:u8",
                                        "99999999999999999999999x1:u8",
                                        "4294967295x4294967295x4294967295:f32le"};
  for (const std::string& spec : bad) {
    const std::string message = error_of([&] { parse_raw_format(spec); });
    EXPECT_EQ(message.rfind("--raw: ", 0), 0u) << "spec \"" << spec << "\": " << message;
  }
  EXPECT_CONTAINS(error_of([] { parse_raw_format("4x4:u24"); }),
                  "u8, u16le, u16be, i16le, i16be, f32le");
  EXPECT_CONTAINS(error_of([] { parse_raw_format("0x5:u8"); }), "width");
  EXPECT_CONTAINS(error_of([] { parse_raw_format("256x:u8"); }), "height");
  EXPECT_CONTAINS(error_of([] { parse_raw_format("4294967295x4294967295x4294967295:f32le"); }),
                  "overflow");
}

// Found by fuzz/raw_format_fuzzer: a control character in the spec went into the message, and a
// newline made it two lines.
TEST(RawFormat, MessagesAreOnePrintableLineWhateverTheSpec) {
  for (const std::string& spec :
       {std::string("3x3x3x\x13:u8"), std::string("12x10\n:u8"), std::string("4x4:u8\n"),
        std::string("4\rx4:u8"), std::string(200, 'x') + ":u8", std::string("1\x7f") + "x1:u8"}) {
    const std::string message = error_of([&] { parse_raw_format(spec); });
    EXPECT_EQ(message.rfind("--raw: ", 0), 0u) << message;
    EXPECT_TRUE(std::all_of(message.begin(), message.end(), [](char c) {
      return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f;
    })) << message;
    EXPECT_LT(message.size(), 300u) << message;
  }
  EXPECT_CONTAINS(error_of([] { parse_raw_format("12x10\n:u8"); }), "\"12x10?:u8\"");
}

TEST(RawFormat, SwapToNativeGivesTheEncodedValues) {
  for (ByteOrder order : {ByteOrder::little, ByteOrder::big}) {
    std::vector<unsigned char> bytes = encode_u16({0x1234, 0xFEDC, 7}, order);
    swap_to_native(bytes.data(), 3, 2, order);
    std::uint16_t values[3];
    std::memcpy(values, bytes.data(), sizeof values);
    EXPECT_EQ(values[0], 0x1234);
    EXPECT_EQ(values[1], 0xFEDC);
    EXPECT_EQ(values[2], 7);

    bytes.clear();
    append(bytes, 0x01020304u, 4, order);
    append(bytes, 0xA0B0C0D0u, 4, order);
    swap_to_native(bytes.data(), 2, 4, order);
    std::uint32_t words[2];
    std::memcpy(words, bytes.data(), sizeof words);
    EXPECT_EQ(words[0], 0x01020304u);
    EXPECT_EQ(words[1], 0xA0B0C0D0u);
  }
  // The host is one or the other; the probe must agree with the compiler where it can tell.
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__)
  EXPECT_EQ(native_byte_order() == ByteOrder::little, __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__);
#endif
}

}  // namespace
}  // namespace mvox
