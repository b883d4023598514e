// Stacks of files are listed when the input is opened and each file is opened again at its
// turn. A file replaced by a FIFO meanwhile kept the run waiting in open() for a writer that
// never came; it is refused instead, naming the file, for every format that opens its files
// again by name: raw slices, TIFF stacks, DICOM series (image stacks: image_stack_source_test).
//
// Each read runs on a thread of its own: should it wait for the FIFO's writer, the test opens
// the FIFO for writing to release it and fails, rather than hang the suite.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "dicom_series.h"
#include "dicom_writer.h"
#include "error_capture.h"
#include "file_io.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"
#include "tiff_stack_files.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::ScratchDirectory;

// Opens `inputs`, replaces `replaced` by a FIFO, then reads every slice: the message must name
// the FIFO as no longer a regular file, at once.
void expect_fifo_refused(const std::vector<std::string>& inputs,
                         const std::optional<RawFormat>& raw, const std::string& replaced) {
  std::unique_ptr<SliceSource> source = open_slice_source(inputs, raw);
  fs::remove(replaced);
  ASSERT_EQ(::mkfifo(replaced.c_str(), 0600), 0);
  std::future<std::string> message = std::async(std::launch::async, [&] {
    return error_of([&] {
      SliceView slice;
      while (source->next_slice(&slice)) {
      }
    });
  });
  if (message.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    // Waiting in open() for a writer: give it one, which closes at once.
    const int fd = ::open(replaced.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
    message.wait();
    FAIL() << "the read waited for a writer of the FIFO " << replaced;
  }
  EXPECT_CONTAINS(message.get(), replaced + ": is no longer a regular file");
}

TEST(ReplacedSliceFiles, ARawSliceReplacedByAFifoAfterListingIsRefused) {
  ScratchDirectory dir;
  std::vector<std::string> files;
  for (int k = 0; k < 3; ++k) {
    files.push_back(dir / ("s" + std::to_string(k) + ".raw"));
    test::write_bytes(files.back(), std::string(35, static_cast<char>(k)));
  }
  expect_fifo_refused(files, parse_raw_format("7x5:u8"), files[1]);
}

TEST(ReplacedSliceFiles, ATiffFileOfAStackReplacedByAFifoAfterListingIsRefused) {
  namespace tiff = test::tiff_stack_files;
  ScratchDirectory dir;
  const std::vector<std::uint8_t> samples(std::size_t{tiff::kWidth} * tiff::kHeight * 3, 9);
  for (std::uint32_t k = 0; k < 3; ++k)
    tiff::write_stack(dir / ("s" + std::to_string(k) + ".tif"), samples, tiff::kWidth,
                      tiff::kHeight, k, 1, tiff::kLayouts[0]);
  expect_fifo_refused({dir.str()}, std::nullopt, dir / "s1.tif");
}

TEST(ReplacedSliceFiles, ADicomFileOfASeriesReplacedByAFifoAfterListingIsRefused) {
  ScratchDirectory dir;
  test::DicomSliceSpec spec;
  spec.width = 6;
  spec.height = 5;
  test::dicom_series::write_series(dir.str(), "s", spec, 3, {0, 0, 0}, 1.0);
  expect_fifo_refused({dir.str()}, std::nullopt, dir / "s1.dcm");
}

}  // namespace
}  // namespace mvox
