// Slice readers: file listing and natural order, --raw parsing, image stacks, raw slices and raw
// volumes. Every file a test reads is written by the test into a fresh temporary directory.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "error.h"
#include "error_capture.h"
#include "gtest/gtest.h"
#include "read/image_stack/image_stack_source.h"
#include "read/input_files.h"
#include "read/input_format.h"
#include "read/natural_sort.h"
#include "read/raw/raw_format.h"
#include "read/raw/raw_slices_source.h"
#include "read/raw/raw_volume_source.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::error_of;

// ---------------------------------------------------------------------------------------------
// Helpers

// A directory of its own under the system temp directory, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::random_device random;
    const std::string name = "mvox_readers_test_" + std::to_string(::getpid()) + "_" +
                             std::to_string(random()) + std::to_string(random());
    path_ = fs::temp_directory_path() / name;
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string str() const { return path_.string(); }

 private:
  fs::path path_;
};

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

void touch(const std::string& path) { write_bytes(path, {}); }

// Appends `value` as `byte_count` bytes in the given order, independent of the host's order.
void append(std::vector<unsigned char>& bytes, std::uint32_t value, int byte_count,
            ByteOrder order) {
  for (int i = 0; i < byte_count; ++i) {
    const int shift = order == ByteOrder::little ? 8 * i : 8 * (byte_count - 1 - i);
    bytes.push_back(static_cast<unsigned char>(value >> shift));
  }
}

std::vector<unsigned char> encode_u16(const std::vector<std::uint16_t>& values, ByteOrder order) {
  std::vector<unsigned char> bytes;
  for (std::uint16_t v : values) append(bytes, v, 2, order);
  return bytes;
}

std::vector<unsigned char> encode_i16(const std::vector<std::int16_t>& values, ByteOrder order) {
  std::vector<unsigned char> bytes;
  for (std::int16_t v : values) append(bytes, static_cast<std::uint16_t>(v), 2, order);
  return bytes;
}

std::vector<unsigned char> encode_f32(const std::vector<float>& values, ByteOrder order) {
  std::vector<unsigned char> bytes;
  for (float v : values) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, 4);
    append(bytes, bits, 4, order);
  }
  return bytes;
}

// Reads every slice of `source` as samples of type T, checking the view against info() and
// that the view always points into the same memory, reused: one slice buffer, or the
// working_bytes() the source says it holds (RawVolumeSource reads several small slices at once).
template <typename T>
std::vector<std::vector<T>> read_all(SliceSource& source) {
  const VolumeInfo& info = source.info();
  std::vector<std::vector<T>> slices;
  const char* first_buffer = nullptr;
  SliceView view;
  while (source.next_slice(&view)) {
    EXPECT_EQ(view.width, info.width);
    EXPECT_EQ(view.height, info.height);
    EXPECT_EQ(view.type, info.type);
    EXPECT_EQ(sample_bytes(view.type), sizeof(T));
    EXPECT_GE(view.row_stride_bytes, view.width * sizeof(T));
    const auto* start = static_cast<const char*>(view.samples);
    if (first_buffer == nullptr) first_buffer = start;
    const std::size_t slice_bytes = view.row_stride_bytes * view.height;
    if (source.working_bytes() == 0) {
      EXPECT_EQ(start, first_buffer) << "slice " << slices.size() << " moved buffers";
    } else {
      EXPECT_LE(first_buffer, start) << "slice " << slices.size() << " left the buffer";
      EXPECT_LE(start + slice_bytes, first_buffer + source.working_bytes())
          << "slice " << slices.size() << " left the buffer";
    }
    std::vector<T> samples(static_cast<std::size_t>(view.width) * view.height);
    for (std::uint32_t y = 0; y < view.height; ++y) {
      std::memcpy(&samples[static_cast<std::size_t>(y) * view.width],
                  static_cast<const char*>(view.samples) + y * view.row_stride_bytes,
                  view.width * sizeof(T));
    }
    slices.push_back(std::move(samples));
  }
  EXPECT_FALSE(source.next_slice(&view)) << "a finished source must stay finished";
  EXPECT_EQ(slices.size(), info.depth);
  return slices;
}

// Opens the source and reads it to the end, so a refusal at any slice surfaces.
void read_through(const std::vector<std::string>& inputs, const std::optional<RawFormat>& raw) {
  std::unique_ptr<SliceSource> source = open_slice_source(inputs, raw);
  SliceView view;
  while (source->next_slice(&view)) {
  }
}

std::string file_name(const std::string& path) { return fs::path(path).filename().string(); }

// ---------------------------------------------------------------------------------------------
// natural_sort.h

TEST(NaturalSort, DigitRunsCompareByValue) {
  EXPECT_TRUE(natural_less("slice2", "slice10"));
  EXPECT_FALSE(natural_less("slice10", "slice2"));
  EXPECT_TRUE(natural_less("CThead.9", "CThead.10"));
  EXPECT_TRUE(natural_less("a9b", "a10a"));  // the number decides before the text after it
  EXPECT_TRUE(natural_less("img", "img1"));  // a prefix comes first
  EXPECT_TRUE(natural_less("s1_2", "s1_10"));

  std::vector<std::string> names = {"slice10", "slice1",  "slice12", "slice3",
                                    "slice2",  "slice11", "slice9",  "slice4"};
  natural_sort(names);
  EXPECT_EQ(names, (std::vector<std::string>{"slice1", "slice2", "slice3", "slice4", "slice9",
                                             "slice10", "slice11", "slice12"}));
}

TEST(NaturalSort, LeadingZerosAndLongRunsDoNotOverflow) {
  EXPECT_TRUE(natural_less("a007", "a10"));
  EXPECT_TRUE(natural_less("a0009", "a10"));
  const std::string forty_nines(40, '9');
  const std::string one_then_forty_zeros = "1" + std::string(40, '0');
  EXPECT_TRUE(natural_less("x" + forty_nines, "x" + one_then_forty_zeros));
  EXPECT_FALSE(natural_less("x" + one_then_forty_zeros, "x" + forty_nines));
  // Many leading zeros do not make a number big.
  EXPECT_TRUE(natural_less("x" + std::string(60, '0') + "5", "x6"));
  // Same length, differing late: compared digit by digit.
  EXPECT_TRUE(natural_less("x" + std::string(30, '7') + "1", "x" + std::string(30, '7') + "2"));
}

TEST(NaturalSort, TiesAreBrokenDeterministically) {
  // "a7", "a07", "a007" are the same number; exactly one order holds between any two.
  const std::vector<std::string> same = {"a7", "a07", "a007"};
  for (const auto& p : same) {
    EXPECT_FALSE(natural_less(p, p));
    for (const auto& q : same) {
      if (p != q) EXPECT_NE(natural_less(p, q), natural_less(q, p)) << p << " " << q;
    }
  }
  std::vector<std::string> forward = {"a7", "a07", "a007", "a8"};
  std::vector<std::string> backward(forward.rbegin(), forward.rend());
  natural_sort(forward);
  natural_sort(backward);
  EXPECT_EQ(forward, backward);
  EXPECT_EQ(forward.back(), "a8");
}

TEST(NaturalSort, IsAStrictWeakOrderOnTrickyNames) {
  // Digits next to characters below and above '0'..'9' in ASCII, prefixes, zeros, high bytes.
  const std::vector<std::string> names = {"",
                                          "a",
                                          "a0",
                                          "a00",
                                          "a1",
                                          "a01",
                                          "a1b",
                                          "a1/",
                                          "a1:",
                                          "a/",
                                          "a:",
                                          "a10",
                                          "a2",
                                          "A2",
                                          "a_2",
                                          "a-2",
                                          "a\xff"
                                          "1",
                                          "1",
                                          "01",
                                          "10",
                                          "9",
                                          "9a",
                                          "a2b3",
                                          "a2b10"};
  for (const auto& a : names) {
    EXPECT_FALSE(natural_less(a, a)) << a;
    for (const auto& b : names) {
      if (a != b) EXPECT_NE(natural_less(a, b), natural_less(b, a)) << a << " | " << b;
      for (const auto& c : names) {
        if (natural_less(a, b) && natural_less(b, c)) {
          EXPECT_TRUE(natural_less(a, c)) << a << " < " << b << " < " << c;
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// raw_format.h

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

// ---------------------------------------------------------------------------------------------
// input_files.h

TEST(InputFiles, DirectoryKeepsSliceImagesInNaturalOrder) {
  TempDir dir;
  for (const char* name : {"slice10.png", "slice2.PNG", "slice1.tif", "slice3.JpEg", ".hidden.png",
                           "notes.txt", "noextension", "sub/slice4.png"}) {
    touch(dir / name);
  }
  EXPECT_EQ(list_input_files({dir.str()}, InputKind::image_stack),
            (std::vector<std::string>{dir / "slice1.tif", dir / "slice2.PNG", dir / "slice3.JpEg",
                                      dir / "slice10.png"}));
  EXPECT_EQ(
      list_input_files({dir.str()}, InputKind::raw_files),
      (std::vector<std::string>{dir / "noextension", dir / "notes.txt", dir / "slice1.tif",
                                dir / "slice2.PNG", dir / "slice3.JpEg", dir / "slice10.png"}));
}

TEST(InputFiles, GlobAndExplicitFilesAreSortedNaturally) {
  TempDir dir;
  for (const char* name :
       {"CThead.10", "CThead.9", "CThead.1", "CThead.100", "CThead.2", "desc.txt"}) {
    touch(dir / name);
  }
  EXPECT_EQ(list_input_files({dir / "CThead.*"}, InputKind::raw_files),
            (std::vector<std::string>{dir / "CThead.1", dir / "CThead.2", dir / "CThead.9",
                                      dir / "CThead.10", dir / "CThead.100"}));
  EXPECT_EQ(list_input_files({dir / "CThead.10", dir / "CThead.9", dir / "CThead.2"},
                             InputKind::image_stack),
            (std::vector<std::string>{dir / "CThead.2", dir / "CThead.9", dir / "CThead.10"}));
}

TEST(InputFiles, RefusalsNameTheInput) {
  TempDir dir;
  fs::create_directories(dir / "empty");
  fs::create_directories(dir / "only_hidden");
  touch(dir / "only_hidden/.slice1.png");
  touch(dir / "no_images/readme.txt");
  touch(dir / "no_images/CThead.1");

  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "missing"}, InputKind::image_stack); }),
                  dir / "missing");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "nope*.png"}, InputKind::image_stack); }),
                  dir / "nope*.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "empty"}, InputKind::raw_files); }),
                  dir / "empty");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "only_hidden"}, InputKind::raw_files); }),
                  dir / "only_hidden");
  const std::string no_images =
      error_of([&] { list_input_files({dir / "no_images"}, InputKind::image_stack); });
  EXPECT_CONTAINS(no_images, dir / "no_images");
  EXPECT_CONTAINS(no_images, "png");
  // The same directory is fine for raw slices.
  EXPECT_EQ(list_input_files({dir / "no_images"}, InputKind::raw_files).size(), 2u);
  EXPECT_CONTAINS(error_of([] { list_input_files({}, InputKind::image_stack); }), "INPUT");
}

TEST(InputFiles, EntriesNamedLikeSlicesThatAreNoFilesAreRefusedNotSkipped) {
  TempDir dir;
  touch(dir / "stack/s1.png");
  touch(dir / "stack/s3.png");
  fs::create_directories(dir / "stack/notes");  // no slice name: skipped
  EXPECT_EQ(list_input_files({dir / "stack"}, InputKind::image_stack).size(), 2u);
  // Skipping these would close the gap of a lost slice without a word.
  fs::create_symlink(dir / "gone.png", dir / "stack/s2.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "stack"}, InputKind::image_stack); }),
                  dir / "stack/s2.png: is a dangling symbolic link");
  EXPECT_CONTAINS(
      error_of([&] { list_input_files({dir / "stack/s*.png"}, InputKind::image_stack); }),
      dir / "stack/s2.png: is a dangling symbolic link");
  fs::remove(dir / "stack/s2.png");
  fs::create_directories(dir / "stack/s2.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "stack"}, InputKind::image_stack); }),
                  dir / "stack/s2.png: is a directory");
  // Raw slices have no extension: any dangling name counts, a directory is skipped.
  touch(dir / "raw/CThead.1");
  fs::create_directories(dir / "raw/CThead.2");
  EXPECT_EQ(list_input_files({dir / "raw"}, InputKind::raw_files).size(), 1u);
  fs::create_symlink(dir / "gone", dir / "raw/CThead.3");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "raw"}, InputKind::raw_files); }),
                  dir / "raw/CThead.3: is a dangling symbolic link");
}

// ---------------------------------------------------------------------------------------------
// image_stack_source.h

// 8-bit value of pixel (x, y) of slice `index` (1-based, as in the file name).
std::uint8_t slice_pixel(int index, int x, int y) {
  return static_cast<std::uint8_t>(index * 16 + x + 2 * y);
}

TEST(ImageStack, ReadsSlicesInNaturalOrder) {
  TempDir dir;
  constexpr int kWidth = 7;  // odd and unequal sizes catch swapped axes
  constexpr int kHeight = 5;
  constexpr int kCount = 12;
  for (int index : {7, 12, 1, 10, 3, 11, 2, 9, 5, 4, 8, 6}) {  // scrambled write order
    cv::Mat image(kHeight, kWidth, CV_8U);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) image.at<std::uint8_t>(y, x) = slice_pixel(index, x, y);
    }
    ASSERT_TRUE(cv::imwrite(dir / ("slice" + std::to_string(index) + ".png"), image));
  }
  touch(dir / "notes.txt");  // not an image: the directory listing skips it

  std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, std::nullopt);
  ASSERT_NE(dynamic_cast<ImageStackSource*>(source.get()), nullptr);
  EXPECT_EQ(source->info().width, static_cast<std::uint32_t>(kWidth));
  EXPECT_EQ(source->info().height, static_cast<std::uint32_t>(kHeight));
  EXPECT_EQ(source->info().depth, static_cast<std::uint32_t>(kCount));
  EXPECT_EQ(source->info().type, SampleType::u8);
  EXPECT_EQ(source->info().spacing[2], 1.0);

  const auto slices = read_all<std::uint8_t>(*source);
  ASSERT_EQ(slices.size(), static_cast<std::size_t>(kCount));
  for (int k = 0; k < kCount; ++k) {
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        ASSERT_EQ(slices[k][y * kWidth + x], slice_pixel(k + 1, x, y))
            << "slice " << k << " x " << x << " y " << y;
      }
    }
  }
}

// Writes two 16-bit slices with values beyond 8 and 15 bits and reads them back exactly.
template <typename T>
void expect_16_bit_round_trip(const std::string& extension, int cv_type, SampleType type,
                              const std::vector<T>& values) {
  TempDir dir;
  constexpr int kWidth = 5;
  constexpr int kHeight = 3;
  ASSERT_EQ(values.size(), static_cast<std::size_t>(kWidth * kHeight));
  std::vector<std::vector<T>> written;
  for (int index = 1; index <= 2; ++index) {
    cv::Mat image(kHeight, kWidth, cv_type);
    std::vector<T> slice = values;
    if (index == 2) std::reverse(slice.begin(), slice.end());
    for (int i = 0; i < kWidth * kHeight; ++i) image.at<T>(i / kWidth, i % kWidth) = slice[i];
    ASSERT_TRUE(cv::imwrite(dir / ("s" + std::to_string(index) + extension), image));
    written.push_back(slice);
  }
  std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, std::nullopt);
  EXPECT_EQ(source->info().type, type);
  EXPECT_EQ(read_all<T>(*source), written);
}

TEST(ImageStack, Png16BitRoundTripsExactly) {
  expect_16_bit_round_trip<std::uint16_t>(
      ".png", CV_16U, SampleType::u16,
      {0, 1, 255, 256, 1000, 3272, 32767, 32768, 40000, 50001, 65534, 65535, 12345, 300, 7});
}

TEST(ImageStack, Tiff16BitRoundTripsExactly) {
  expect_16_bit_round_trip<std::uint16_t>(
      ".tif", CV_16U, SampleType::u16,
      {0, 1, 255, 256, 1000, 3272, 32767, 32768, 40000, 50001, 65534, 65535, 12345, 300, 7});
}

TEST(ImageStack, TiffSigned16BitKeepsNegativeValues) {
  expect_16_bit_round_trip<std::int16_t>(
      ".tiff", CV_16S, SampleType::i16,
      {-32768, -1024, -1, 0, 1, 255, 256, 32767, -300, 1000, -2, 3, 4, 5, 6});
}

TEST(ImageStack, Png8BitRoundTripsExactly) {
  TempDir dir;
  cv::Mat image(4, 64, CV_8U);
  for (int i = 0; i < 256; ++i) image.at<std::uint8_t>(i / 64, i % 64) = static_cast<uint8_t>(i);
  ASSERT_TRUE(cv::imwrite(dir / "only.png", image));
  std::unique_ptr<SliceSource> source = open_slice_source({dir / "only.png"}, std::nullopt);
  const auto slices = read_all<std::uint8_t>(*source);
  ASSERT_EQ(slices.size(), 1u);
  for (int i = 0; i < 256; ++i) ASSERT_EQ(slices[0][i], i);
}

TEST(ImageStack, RefusesSliceOfAnotherSize) {
  TempDir dir;
  ASSERT_TRUE(cv::imwrite(dir / "slice1.png", cv::Mat(5, 7, CV_8U, cv::Scalar(1))));
  ASSERT_TRUE(cv::imwrite(dir / "slice2.png", cv::Mat(5, 7, CV_8U, cv::Scalar(2))));
  ASSERT_TRUE(cv::imwrite(dir / "slice10.png", cv::Mat(7, 5, CV_8U, cv::Scalar(3))));
  const std::string message = error_of([&] { read_through({dir.str()}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "slice10.png: image is 5x7, expected 7x5");
}

TEST(ImageStack, RefusesSliceOfAnotherBitDepth) {
  TempDir dir;
  ASSERT_TRUE(cv::imwrite(dir / "slice1.png", cv::Mat(5, 7, CV_16U, cv::Scalar(1000))));
  ASSERT_TRUE(cv::imwrite(dir / "slice2.png", cv::Mat(5, 7, CV_8U, cv::Scalar(2))));
  const std::string message = error_of([&] { read_through({dir.str()}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "slice2.png: image is 8-bit");
  EXPECT_CONTAINS(message, "16-bit");
}

TEST(ImageStack, RefusesColourImages) {
  TempDir dir;
  fs::create_directories(dir / "first");
  fs::create_directories(dir / "later");
  ASSERT_TRUE(cv::imwrite(dir / "first/s1.png", cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))));
  ASSERT_TRUE(cv::imwrite(dir / "first/s2.png", cv::Mat(4, 4, CV_8U, cv::Scalar(1))));
  ASSERT_TRUE(cv::imwrite(dir / "later/s1.png", cv::Mat(4, 4, CV_8U, cv::Scalar(1))));
  ASSERT_TRUE(cv::imwrite(dir / "later/s2.bmp", cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))));

  // The first slice is decoded when the source opens, so info() is exact: refused right there.
  const std::string first = error_of([&] { open_slice_source({dir / "first"}, std::nullopt); });
  EXPECT_CONTAINS(first, dir / "first/s1.png: colour image");
  EXPECT_CONTAINS(first, "convert to grayscale first");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "later"}, std::nullopt); }),
                  dir / "later/s2.bmp: colour image");
}

TEST(ImageStack, RefusesUnsupportedBitDepth) {
  TempDir dir;
  ASSERT_TRUE(cv::imwrite(dir / "float.tif", cv::Mat(4, 4, CV_32F, cv::Scalar(1.5))));
  // Directly: through open_slice_source a TIFF-only input goes to TiffStackSource, which reads
  // float pages (tiff_stack_test.cpp).
  const std::string message = error_of([&] { ImageStackSource source({dir / "float.tif"}); });
  EXPECT_CONTAINS(message, dir / "float.tif: image is 32-bit float");
}

TEST(ImageStack, RefusesCorruptAndTruncatedImages) {
  TempDir dir;
  // Noise compresses badly, so half the file cuts deep into the pixel data.
  cv::Mat noise(64, 64, CV_16U);
  cv::randu(noise, 0, 65535);
  fs::create_directories(dir / "truncated");
  ASSERT_TRUE(cv::imwrite(dir / "truncated/s1.png", noise));
  ASSERT_TRUE(cv::imwrite(dir / "truncated/s2.png", noise));
  fs::resize_file(dir / "truncated/s2.png", fs::file_size(dir / "truncated/s2.png") / 2);
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "truncated"}, std::nullopt); }),
                  dir / "truncated/s2.png: truncated PNG: the file ends at byte");

  // libjpeg would decode a truncated JPEG into a grey bottom with only a warning.
  fs::create_directories(dir / "truncated_jpeg");
  cv::Mat noise8(64, 64, CV_8U);
  cv::randu(noise8, 0, 255);
  ASSERT_TRUE(cv::imwrite(dir / "truncated_jpeg/s1.jpg", noise8));
  ASSERT_TRUE(cv::imwrite(dir / "truncated_jpeg/s2.jpg", noise8));
  fs::resize_file(dir / "truncated_jpeg/s2.jpg", fs::file_size(dir / "truncated_jpeg/s2.jpg") - 2);
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "truncated_jpeg"}, std::nullopt); }),
                  dir / "truncated_jpeg/s2.jpg: truncated JPEG");
  // OpenCV's own readers say why, in the one message.
  fs::create_directories(dir / "truncated_pgm");
  ASSERT_TRUE(cv::imwrite(dir / "truncated_pgm/s1.pgm", noise8));
  ASSERT_TRUE(cv::imwrite(dir / "truncated_pgm/s2.pgm", noise8));
  fs::resize_file(dir / "truncated_pgm/s2.pgm", fs::file_size(dir / "truncated_pgm/s2.pgm") / 2);
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "truncated_pgm"}, std::nullopt); }),
      dir / "truncated_pgm/s2.pgm: cannot decode image: Unexpected end of input stream");

  const std::string text = "this is not an image";
  write_bytes(dir / "garbage/s1.png", std::vector<unsigned char>(text.begin(), text.end()));
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "garbage"}, std::nullopt); }),
                  dir / "garbage/s1.png: cannot read image");

  touch(dir / "empty_file/s1.tif");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "empty_file"}, std::nullopt); }),
                  dir / "empty_file/s1.tif");
}

TEST(ImageStack, RefusesMissingInputs) {
  TempDir dir;
  fs::create_directories(dir / "empty");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "empty"}, std::nullopt); }), dir / "empty");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "missing.png"}, std::nullopt); }),
                  dir / "missing.png");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "slice*.png"}, std::nullopt); }),
                  dir / "slice*.png");
  // A constructor given a file that vanished after listing names it too.
  EXPECT_CONTAINS(error_of([&] { ImageStackSource source({dir / "gone.png"}); }), dir / "gone.png");
}

// ---------------------------------------------------------------------------------------------
// raw_slices_source.h, raw_volume_source.h

constexpr int kRawWidth = 5;
constexpr int kRawHeight = 3;
constexpr int kRawSamples = kRawWidth * kRawHeight;

// u16 sample i of slice k: spans values above 255 and above 32767.
std::uint16_t raw_u16(int k, int i) {
  return static_cast<std::uint16_t>(40000 + k * 1000 + i * 1711);
}
std::int16_t raw_i16(int k, int i) { return static_cast<std::int16_t>(-20000 + k * 7 + i * 2500); }
float raw_f32(int k, int i) { return (i % 2 ? -1.0f : 1.0f) * (0.1f + k) * std::pow(10.0f, i - 7); }

template <typename T>
std::vector<T> raw_slice(T (*sample)(int, int), int k) {
  std::vector<T> slice(kRawSamples);
  for (int i = 0; i < kRawSamples; ++i) slice[i] = sample(k, i);
  return slice;
}

// Writes slices s1, s2, s10 (k = 0, 1, 2) in scrambled order and reads them through the factory.
template <typename T>
void expect_raw_slices(const std::string& spec, T (*sample)(int, int),
                       std::vector<unsigned char> (*encode)(const std::vector<T>&, ByteOrder),
                       ByteOrder order, SampleType type) {
  TempDir dir;
  const char* names[] = {"s1", "s2", "s10"};
  for (int k : {2, 0, 1}) write_bytes(dir / names[k], encode(raw_slice(sample, k), order));
  std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, parse_raw_format(spec));
  ASSERT_NE(dynamic_cast<RawSlicesSource*>(source.get()), nullptr);
  EXPECT_EQ(source->info().width, static_cast<std::uint32_t>(kRawWidth));
  EXPECT_EQ(source->info().height, static_cast<std::uint32_t>(kRawHeight));
  EXPECT_EQ(source->info().depth, 3u);
  EXPECT_EQ(source->info().type, type);
  const auto slices = read_all<T>(*source);
  ASSERT_EQ(slices.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(slices[k], raw_slice(sample, k)) << "slice " << k;
}

TEST(RawSlices, U16BigAndLittleEndianGiveNativeValues) {
  expect_raw_slices<std::uint16_t>("5x3:u16be", raw_u16, encode_u16, ByteOrder::big,
                                   SampleType::u16);
  expect_raw_slices<std::uint16_t>("5x3:u16le", raw_u16, encode_u16, ByteOrder::little,
                                   SampleType::u16);
}

TEST(RawSlices, I16KeepsNegativeValues) {
  expect_raw_slices<std::int16_t>("5x3:i16be", raw_i16, encode_i16, ByteOrder::big,
                                  SampleType::i16);
  expect_raw_slices<std::int16_t>("5x3:i16le", raw_i16, encode_i16, ByteOrder::little,
                                  SampleType::i16);
}

TEST(RawSlices, F32LittleEndianGivesNativeValues) {
  expect_raw_slices<float>("5x3:f32le", raw_f32, encode_f32, ByteOrder::little, SampleType::f32);
}

TEST(RawSlices, ByteOrderMatters) {
  // Big-endian data read as little-endian gives each value with its bytes swapped; this shows the
  // order in the spec is honoured rather than ignored.
  TempDir dir;
  write_bytes(dir / "s1", encode_u16(raw_slice(raw_u16, 0), ByteOrder::big));
  std::unique_ptr<SliceSource> source =
      open_slice_source({dir / "s1"}, parse_raw_format("5x3:u16le"));
  const auto slices = read_all<std::uint16_t>(*source);
  ASSERT_EQ(slices.size(), 1u);
  for (int i = 0; i < kRawSamples; ++i) {
    const std::uint16_t v = raw_u16(0, i);
    EXPECT_EQ(slices[0][i], static_cast<std::uint16_t>((v >> 8) | (v << 8)));
  }
}

TEST(RawSlices, RefusesFileOfWrongSize) {
  TempDir dir;
  write_bytes(dir / "CThead.1", encode_u16(raw_slice(raw_u16, 0), ByteOrder::big));
  std::vector<unsigned char> long_slice = encode_u16(raw_slice(raw_u16, 1), ByteOrder::big);
  long_slice.push_back(0);
  write_bytes(dir / "CThead.2", long_slice);
  write_bytes(dir / "CThead.3", encode_u16(raw_slice(raw_u16, 2), ByteOrder::big));
  const std::string message =
      error_of([&] { read_through({dir / "CThead.*"}, parse_raw_format("5x3:u16be")); });
  EXPECT_CONTAINS(message, dir / "CThead.2: file is 31 bytes, expected 30");

  // A file that changes size after the source opened is caught when its slice is read.
  fs::resize_file(dir / "CThead.2", 30);
  RawSlicesSource source(list_input_files({dir.str()}, InputKind::raw_files),
                         parse_raw_format("5x3:u16be"));
  fs::resize_file(dir / "CThead.3", 29);
  SliceView view;
  EXPECT_TRUE(source.next_slice(&view));
  EXPECT_TRUE(source.next_slice(&view));
  EXPECT_CONTAINS(error_of([&] { source.next_slice(&view); }), dir / "CThead.3: file is 29 bytes");
}

TEST(RawVolume, ReadsSliceBySliceEqualToTheWrittenData) {
  TempDir dir;
  constexpr int kDepth = 6;
  std::vector<std::uint16_t> all;
  for (int k = 0; k < kDepth; ++k) {
    const std::vector<std::uint16_t> slice = raw_slice(raw_u16, k);
    all.insert(all.end(), slice.begin(), slice.end());
  }
  write_bytes(dir / "volume_5x3x6_u16be.raw", encode_u16(all, ByteOrder::big));
  std::unique_ptr<SliceSource> source =
      open_slice_source({dir / "volume_5x3x6_u16be.raw"}, parse_raw_format("5x3x6:u16be"));
  ASSERT_NE(dynamic_cast<RawVolumeSource*>(source.get()), nullptr);
  EXPECT_EQ(source->info().width, static_cast<std::uint32_t>(kRawWidth));
  EXPECT_EQ(source->info().height, static_cast<std::uint32_t>(kRawHeight));
  EXPECT_EQ(source->info().depth, static_cast<std::uint32_t>(kDepth));
  EXPECT_EQ(source->info().type, SampleType::u16);
  const auto slices = read_all<std::uint16_t>(*source);
  ASSERT_EQ(slices.size(), static_cast<std::size_t>(kDepth));
  for (int k = 0; k < kDepth; ++k) EXPECT_EQ(slices[k], raw_slice(raw_u16, k)) << "slice " << k;
}

TEST(RawVolume, ReadsU8AndF32Volumes) {
  TempDir dir;
  std::vector<unsigned char> bytes(7 * 5 * 4);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 3);
  write_bytes(dir / "engine.raw", bytes);
  RawVolumeSource u8_source(dir / "engine.raw", parse_raw_format("7x5x4:u8"));
  const auto u8_slices = read_all<std::uint8_t>(u8_source);
  ASSERT_EQ(u8_slices.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_TRUE(std::equal(u8_slices[k].begin(), u8_slices[k].end(), bytes.begin() + k * 35));
  }

  std::vector<float> all;
  for (int k = 0; k < 2; ++k) {
    const std::vector<float> slice = raw_slice(raw_f32, k);
    all.insert(all.end(), slice.begin(), slice.end());
  }
  write_bytes(dir / "f.raw", encode_f32(all, ByteOrder::little));
  RawVolumeSource f32_source(dir / "f.raw", parse_raw_format("5x3x2:f32le"));
  const auto f32_slices = read_all<float>(f32_source);
  ASSERT_EQ(f32_slices.size(), 2u);
  EXPECT_EQ(f32_slices[1], raw_slice(raw_f32, 1));
}

TEST(RawVolume, RefusesFileOfWrongSizeAndWrongInputs) {
  TempDir dir;
  write_bytes(dir / "short.raw", std::vector<unsigned char>(7 * 5 * 4 - 1));
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "short.raw"}, parse_raw_format("7x5x4:u8")); }),
      dir / "short.raw: file is 139 bytes, expected 140");
  write_bytes(dir / "long.raw", std::vector<unsigned char>(7 * 5 * 4 * 2 + 2));
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "long.raw"}, parse_raw_format("7x5x4:u16le")); }),
      dir / "long.raw: file is 282 bytes, expected 280");

  write_bytes(dir / "ok.raw", std::vector<unsigned char>(140));
  EXPECT_CONTAINS(error_of([&] {
                    read_through({dir / "ok.raw", dir / "short.raw"}, parse_raw_format("7x5x4:u8"));
                  }),
                  "one volume file");
  EXPECT_CONTAINS(error_of([&] { read_through({dir.str()}, parse_raw_format("7x5x4:u8")); }),
                  dir.str() + ": is a directory");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "*.raw"}, parse_raw_format("7x5x4:u8")); }),
                  dir / "*.raw: matches 3 files");
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "absent.raw"}, parse_raw_format("7x5x4:u8")); }),
      dir / "absent.raw");
  // A glob that matches exactly one file is fine.
  EXPECT_NO_THROW(read_through({dir / "o*.raw"}, parse_raw_format("7x5x4:u8")));
}

// A volume of many small slices: they are read a chunk of several at a time (one read per
// slice cost more than extracting a slice of a few voxels), each swapped to native order as it
// is handed out, and the chunk is the memory the source says it holds.
std::vector<std::uint16_t> many_slices_u16(int depth) {
  std::vector<std::uint16_t> all;
  for (int k = 0; k < depth; ++k) {
    const std::vector<std::uint16_t> slice = raw_slice(raw_u16, k);
    all.insert(all.end(), slice.begin(), slice.end());
  }
  return all;
}

TEST(RawVolume, ManySmallSlicesAreReadAChunkAtATimeInFixedMemory) {
  TempDir dir;
  constexpr int kDepth = 5000;  // 30-byte slices: 2184 to a 64 KiB chunk, so three chunks
  write_bytes(dir / "v.raw", encode_u16(many_slices_u16(kDepth), ByteOrder::big));
  RawVolumeSource source(dir / "v.raw", parse_raw_format("5x3x5000:u16be"));
  EXPECT_EQ(source.working_bytes(), (RawVolumeSource::kChunkBytes / 30) * 30);
  const auto slices = read_all<std::uint16_t>(source);
  ASSERT_EQ(slices.size(), static_cast<std::size_t>(kDepth));
  for (int k = 0; k < kDepth; ++k) ASSERT_EQ(slices[k], raw_slice(raw_u16, k)) << "slice " << k;

  // A slice larger than a chunk is read alone, in a buffer of its own size.
  const std::size_t big = RawVolumeSource::kChunkBytes + 7;
  write_bytes(dir / "big.raw", std::vector<unsigned char>(2 * big, 9));
  RawVolumeSource big_source(dir / "big.raw", parse_raw_format(std::to_string(big) + "x1x2:u8"));
  EXPECT_EQ(big_source.working_bytes(), big);
  EXPECT_EQ(read_all<std::uint8_t>(big_source).size(), 2u);
}

// Writes `bytes` into the FIFO at `path` in pieces of odd sizes with pauses between, so that
// reads end inside slices, then closes it.
void trickle_into_fifo(const std::string& path, const std::vector<unsigned char>& bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0) << path;
  const std::size_t pieces[] = {1, 7, 29, 100, 3, 64};
  std::size_t done = 0;
  for (int i = 0; done < bytes.size(); ++i) {
    const std::size_t piece = std::min(pieces[i % 6], bytes.size() - done);
    ASSERT_EQ(::write(fd, bytes.data() + done, piece), static_cast<ssize_t>(piece));
    done += piece;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ::close(fd);
}

TEST(RawVolume, APipeIsReadAsItArrivesWhereverItsPiecesEnd) {
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "v.raw").c_str(), 0600), 0);
  constexpr int kDepth = 200;
  std::thread writer([&] {
    trickle_into_fifo(dir / "v.raw", encode_u16(many_slices_u16(kDepth), ByteOrder::big));
  });
  {
    RawVolumeSource source(dir / "v.raw", parse_raw_format("5x3x200:u16be"));
    const auto slices = read_all<std::uint16_t>(source);
    ASSERT_EQ(slices.size(), static_cast<std::size_t>(kDepth));
    for (int k = 0; k < kDepth; ++k) EXPECT_EQ(slices[k], raw_slice(raw_u16, k)) << "slice " << k;
  }
  writer.join();
}

TEST(RawVolume, APipeThatEndsInsideASliceFailsAtThatSlice) {
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "v.raw").c_str(), 0600), 0);
  // Two slices of 35 bytes and ten bytes of the third.
  std::thread writer([&] { trickle_into_fifo(dir / "v.raw", std::vector<unsigned char>(80, 1)); });
  {
    RawVolumeSource source(dir / "v.raw", parse_raw_format("7x5x4:u8"));
    SliceView view;
    EXPECT_TRUE(source.next_slice(&view));
    EXPECT_TRUE(source.next_slice(&view));
    EXPECT_CONTAINS(error_of([&] { source.next_slice(&view); }),
                    dir / "v.raw: file ended at byte 80, expected 105 bytes");
  }
  writer.join();
}

// ---------------------------------------------------------------------------------------------
// Real data, when ../shared/datasets is present (never in the repository).

TEST(SharedDatasets, CtheadReadsAsU16BigEndian) {
  const std::string folder = std::string(MVOX_SHARED_DATASETS) + "/cthead";
  if (!fs::is_directory(folder)) GTEST_SKIP() << folder << " is absent (optional real data)";

  const std::string pattern = folder + "/CThead.*";
  const std::vector<std::string> files = list_input_files({pattern}, InputKind::raw_files);
  ASSERT_EQ(files.size(), 113u);
  for (std::size_t k = 0; k < files.size(); ++k) {
    ASSERT_EQ(file_name(files[k]), "CThead." + std::to_string(k + 1));
  }

  std::unique_ptr<SliceSource> source =
      open_slice_source({pattern}, parse_raw_format("256x256:u16be"));
  EXPECT_EQ(source->info().width, 256u);
  EXPECT_EQ(source->info().height, 256u);
  EXPECT_EQ(source->info().depth, 113u);
  EXPECT_EQ(source->info().type, SampleType::u16);
  // Figures from cthead/INFO.txt (computed there with numpy, >u2).
  std::uint16_t min_value = 65535;
  std::uint16_t max_value = 0;
  double sum = 0;
  std::uint32_t slice_count = 0;
  SliceView view;
  while (source->next_slice(&view)) {
    ++slice_count;
    for (std::uint32_t y = 0; y < view.height; ++y) {
      const auto* row = reinterpret_cast<const std::uint16_t*>(
          static_cast<const char*>(view.samples) + y * view.row_stride_bytes);
      for (std::uint32_t x = 0; x < view.width; ++x) {
        min_value = std::min(min_value, row[x]);
        max_value = std::max(max_value, row[x]);
        sum += row[x];
      }
    }
  }
  EXPECT_EQ(slice_count, 113u);
  EXPECT_EQ(min_value, 0);
  EXPECT_EQ(max_value, 3272);
  EXPECT_NEAR(sum / (256.0 * 256.0 * 113.0), 379.542, 0.001);
}

}  // namespace
}  // namespace mvox
