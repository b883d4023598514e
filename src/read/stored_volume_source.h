#pragma once
// Streams the samples of a volume file whose header has been parsed (NRRD, MetaImage): raw
// samples read slice by slice at their offset, like RawVolumeSource, or a zlib/gzip stream
// decompressed slice by slice. Never the whole volume.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/copied_slices.h"
#include "read/inflate_reader.h"
#include "read/range_readable.h"
#include "read/raw_file.h"
#include "read/read_buffer.h"
#include "read/stored_volume.h"

namespace mvox {

// Where the samples of a StoredVolume are.
struct StoredVolumeData {
  std::string path;  // the data file (the header file itself for attached data)
  // First byte of the samples (of the compressed stream when compressed). With `at_end`, the
  // samples are the last bytes of the file instead, and this is the earliest they may start
  // (the end of an attached header).
  std::uint64_t offset = 0;
  bool at_end = false;
  // Compressed data: bytes of the stream (0: to the end of the file), and decompressed bytes
  // that come before the samples (NRRD's byte skip on gzip data).
  std::uint64_t compressed_bytes = 0;
  std::uint64_t skip_decompressed = 0;
  std::string header;  // the header file, named in messages when the data live elsewhere
};

// The constructor checks, before any slice is read, that the data file holds the whole volume:
// for raw data by its size; for compressed data by the gzip trailer's size when it matches, and
// otherwise by decompressing the stream once without keeping it (a corrupt or short stream is
// refused there, before extraction starts).
// info(): the header's sizes, engine sample type, spacing, origin and axes.
// Compressed data are also refused when the stream is too short to hold the volume at deflate's
// largest ratio (compression_bounds.h), before anything is decompressed: a header may not make
// a 100-byte file cost gigabytes.
// Memory: one slice buffer (of the engine's sample type), allocated at the first slice, plus
// 64 KiB of zlib input, 64 KiB to measure a stream into, and zlib's own 7 KiB + 32 KiB window
// when compressed (working_bytes()). Samples are swapped to native order and signed bytes
// widened to 16 bits in place.
// Throws mvox::Error naming the data file: cannot open, too short (both sizes), corrupt.
// Raw data can be read from anywhere (RangeReadable): slab workers and mvox-mpi's ranks each
// read their own slices; compressed data only in order.
class StoredVolumeSource : public SliceSource, public RangeReadable, public CopiedSlices {
 public:
  // `same_file_as`: for open_range, the whole source's data file, which the path must still
  // name (RawFile).
  StoredVolumeSource(const StoredVolume& volume, StoredVolumeData data,
                     const RawFile* same_file_as = nullptr);

  const VolumeInfo& info() const override { return volume_.info; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override;

  bool range_readable() const override { return volume_.compression == Compression::none; }
  bool slices_are_copied() const override { return volume_.compression == Compression::none; }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override;

  // The file the samples are read from: the header itself for attached data.
  const std::string& data_path() const { return data_.path; }

 private:
  void check_raw_size();
  void check_compressed_size();
  std::string volume_text() const;  // "a 7x5x4 u16 volume (from tooth.nhdr)" for messages
  // Throws mvox::Error for a 32-bit integer sample (native order) that a float cannot hold.
  void check_exact_in_float(const unsigned char* bytes, std::size_t count) const;

  StoredVolume volume_;
  StoredVolumeData data_;
  RawFile file_;
  std::unique_ptr<InflateReader> inflate_;
  ReadBuffer buffer_;  // the current slice, native order, engine's type
  std::uint32_t next_index_ = 0;
  std::uint32_t end_index_ = 0;  // the depth, or a range's end (open_range)
};

// The first min(file size, max_bytes) bytes of `file`, where a text header is. With `complete`,
// the bytes are read 64 KiB first, then four times as many at a time, until complete(text)
// says the header is all there (or the limit is reached): a header of a few hundred bytes in
// front of a large volume then costs one small read, not a megabyte copied and allocated at
// every start.
std::string read_file_start(RawFile& file, std::size_t max_bytes,
                            bool (*complete)(const std::string& text) = nullptr);

// `data_file` as named in the header `header_path`: relative names are relative to the
// header's directory. Throws mvox::Error naming the header when the file does not exist, is a
// directory, or is not a regular file (a FIFO, socket or device), before opening it.
std::string resolve_data_file(const std::string& header_path, const std::string& data_file);

}  // namespace mvox
