#include "read/image_stack/png_plain_decoder.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "read/image_stack/png_bytes.h"

namespace mvox {
namespace {

// Rows are inflated into a buffer of about this many bytes (at least one row): far above the
// 258 bytes zlib's fast path needs, small enough to stay in the cache with the rows it is
// unfiltered into.
constexpr std::size_t kInflateBytes = std::size_t{64} << 10;
// The most the rows buffer keeps between calls.
constexpr std::size_t kKeptBytes = std::size_t{1} << 20;

bool is_letter(unsigned char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

// One chunk of the file, within its bounds.
struct Chunk {
  const unsigned char* type = nullptr;  // 4 letters, then the data, then the CRC
  const unsigned char* data = nullptr;
  std::uint32_t length = 0;

  bool is(const char* name) const { return std::memcmp(type, name, 4) == 0; }
  bool critical() const { return (type[0] & 0x20) == 0; }  // an upper-case first letter
  bool crc_ok() const {
    return png_crc(type, 4 + std::size_t{length}) == png_uint32(data + length);
  }
};

// Walks the chunks after the signature. next() is false at the end of the file or at a chunk
// that does not fit in it or has a type that is not four letters (both refused by libpng).
class Chunks {
 public:
  Chunks(const unsigned char* bytes, std::size_t size) : bytes_(bytes), size_(size), at_(8) {}

  bool next(Chunk* chunk) {
    if (size_ - at_ < 12) return false;
    const std::uint32_t length = png_uint32(bytes_ + at_);
    if (length > 0x7fffffffu || length > size_ - at_ - 12) return false;
    const unsigned char* type = bytes_ + at_ + 4;
    if (!is_letter(type[0]) || !is_letter(type[1]) || !is_letter(type[2]) || !is_letter(type[3]))
      return false;
    chunk->type = type;
    chunk->data = type + 4;
    chunk->length = length;
    at_ += std::size_t{length} + 12;
    return true;
  }

 private:
  const unsigned char* bytes_;
  std::size_t size_;
  std::size_t at_;
};

// PNG's filters (filter method 0), undone for one row of `n` bytes (a multiple of kBpp) with kBpp
// bytes a pixel: `in` is the filtered row, `prior` the row above as unfiltered (zeros for the
// first row). The byte a pixel to the left is carried in a local, not read back from `out`:
// through memory, each byte of Sub, Average and Paeth waited for the store of the one before
// (a third of a run on a stack of Sub-filtered slices). False for a filter type PNG does not
// define.
template <std::size_t kBpp>
bool unfilter_row(unsigned filter, const unsigned char* __restrict in,
                  const unsigned char* __restrict prior, unsigned char* __restrict out,
                  std::size_t n) {
  unsigned left[kBpp] = {};     // the unfiltered byte a pixel to the left
  unsigned up_left[kBpp] = {};  // the byte above that one
  switch (filter) {
    case 0:  // None
      std::memcpy(out, in, n);
      return true;
    case 1:  // Sub: the byte a pixel to the left
      for (std::size_t i = 0; i < n; i += kBpp)
        for (std::size_t k = 0; k < kBpp; ++k) {
          left[k] = (in[i + k] + left[k]) & 0xFF;
          out[i + k] = static_cast<unsigned char>(left[k]);
        }
      return true;
    case 2:  // Up: the byte above
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>(in[i] + prior[i]);
      return true;
    case 3:  // Average of left and above, rounded down
      for (std::size_t i = 0; i < n; i += kBpp)
        for (std::size_t k = 0; k < kBpp; ++k) {
          left[k] = (in[i + k] + ((left[k] + prior[i + k]) >> 1)) & 0xFF;
          out[i + k] = static_cast<unsigned char>(left[k]);
        }
      return true;
    case 4:  // Paeth: whichever of left, above and above-left is nearest left + above - above-left
      for (std::size_t i = 0; i < n; i += kBpp)
        for (std::size_t k = 0; k < kBpp; ++k) {
          const int a = static_cast<int>(left[k]), b = prior[i + k];
          const int c = static_cast<int>(up_left[k]);
          const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
          const int predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
          left[k] = (in[i + k] + static_cast<unsigned>(predicted)) & 0xFF;
          up_left[k] = static_cast<unsigned>(b);
          out[i + k] = static_cast<unsigned char>(left[k]);
        }
      return true;
    default: return false;
  }
}

// PNG stores 16-bit samples big-endian.
void to_native_16(unsigned char* row, std::size_t n) {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  if (first != 1) return;
  for (std::size_t i = 0; i + 1 < n; i += 2) std::swap(row[i], row[i + 1]);
}

struct Header {
  std::uint32_t width = 0, height = 0;
  int bit_depth = 0;
};

// IHDR of a grey, 8- or 16-bit, non-interlaced image with standard compression and filters.
bool read_header(const Chunk& chunk, bool check_crc, Header* header) {
  if (!chunk.is("IHDR") || chunk.length != 13 || (check_crc && !chunk.crc_ok())) return false;
  const unsigned char* d = chunk.data;
  header->width = png_uint32(d);
  header->height = png_uint32(d + 4);
  header->bit_depth = d[8];
  const bool size_ok = header->width >= 1 && header->width <= 0x7fffffffu && header->height >= 1 &&
                       header->height <= 0x7fffffffu;
  return size_ok && (header->bit_depth == 8 || header->bit_depth == 16) && d[9] == 0 &&
         d[10] == 0 && d[11] == 0 && d[12] == 0;
}

// Inflates the image data into batches of rows and unfilters each batch into the slice.
class RowInflater {
 public:
  RowInflater(const Header& header, unsigned char* slice, std::vector<unsigned char>& rows)
      : bpp_(header.bit_depth / 8),
        row_bytes_(std::size_t{header.width} * bpp_),
        stride_(row_bytes_ + 1),
        height_(header.height),
        batch_rows_(std::max<std::size_t>(1, kInflateBytes / stride_)),
        slice_(slice),
        rows_(rows) {
    // A row of zeros after the batch: the row above the first.
    const std::size_t needed = batch_rows_ * stride_ + row_bytes_;
    if (rows_.size() < needed) rows_.resize(needed);
    std::memset(rows_.data() + batch_rows_ * stride_, 0, row_bytes_);
    started_ = inflateInit2(&stream_, 0) == Z_OK;  // 0: the window the stream's header gives
    next_batch();
  }
  ~RowInflater() {
    if (started_) inflateEnd(&stream_);
  }
  RowInflater(const RowInflater&) = delete;
  RowInflater& operator=(const RowInflater&) = delete;

  // The next IDAT chunk's data. False when the stream is damaged, has ended before, or gives
  // more than the image.
  bool feed(const unsigned char* data, std::uint32_t length) {
    if (!started_ || ended_) return false;
    stream_.next_in = const_cast<Bytef*>(data);
    stream_.avail_in = length;
    while (stream_.avail_in > 0) {
      if (stream_.avail_out == 0 && !take_batch()) return false;
      const int status = inflate(&stream_, Z_NO_FLUSH);
      if (status == Z_STREAM_END) {
        ended_ = true;
        return stream_.avail_in == 0;  // bytes after the stream's end: libpng decides
      }
      if (status != Z_OK) return false;
    }
    return true;
  }

  // After the last IDAT chunk: true when the stream ended (its Adler-32 checked by zlib) exactly
  // where the last row did, every row unfiltered.
  bool finish() {
    if (!ended_) return false;
    if (!complete_ && stream_.avail_out == 0 && !take_batch()) return false;
    return complete_ && stream_.avail_out == 1;  // nothing spilled past the image
  }

 private:
  void next_batch() {
    batch_ = std::min<std::size_t>(batch_rows_, height_ - done_);
    stream_.next_out = rows_.data();
    stream_.avail_out = static_cast<uInt>(batch_ * stride_);
  }

  // Unfilters the full batch; then points the stream at the next, or past the image at one
  // spare byte that must stay unwritten.
  bool take_batch() {
    if (complete_) return false;  // the spare byte was written: more data than the image holds
    const unsigned char* zeros = rows_.data() + batch_rows_ * stride_;
    for (std::size_t r = 0; r < batch_; ++r, ++done_) {
      const unsigned char* in = rows_.data() + r * stride_;
      unsigned char* out = slice_ + done_ * row_bytes_;
      const unsigned char* prior = done_ == 0 ? zeros : out - row_bytes_;
      const bool known = bpp_ == 1 ? unfilter_row<1>(in[0], in + 1, prior, out, row_bytes_)
                                   : unfilter_row<2>(in[0], in + 1, prior, out, row_bytes_);
      if (!known) return false;
      // The row above is no longer needed as the file has it: now in native order.
      if (bpp_ == 2 && done_ > 0) to_native_16(out - row_bytes_, row_bytes_);
    }
    if (done_ < height_) {
      next_batch();
      return true;
    }
    if (bpp_ == 2) to_native_16(slice_ + (height_ - 1) * row_bytes_, row_bytes_);
    complete_ = true;
    stream_.next_out = &spare_;
    stream_.avail_out = 1;
    return true;
  }

  const std::size_t bpp_;
  const std::size_t row_bytes_;
  const std::size_t stride_;  // a filter byte, then the row
  const std::size_t height_;
  const std::size_t batch_rows_;
  unsigned char* const slice_;
  std::vector<unsigned char>& rows_;
  z_stream stream_{};
  bool started_ = false;
  bool ended_ = false;
  bool complete_ = false;
  std::size_t done_ = 0;   // rows unfiltered into the slice
  std::size_t batch_ = 0;  // rows in the current batch
  unsigned char spare_ = 0;
};

}  // namespace

bool decode_plain_grey_png(const unsigned char* bytes, std::size_t size,
                           const PngDestination& destination, PngCrcs crcs) {
  if (!has_png_signature(bytes, size)) return false;
  const bool check_crcs = crcs == PngCrcs::check;
  Chunks chunks(bytes, size);
  Chunk chunk;
  Header header;
  if (!chunks.next(&chunk) || !read_header(chunk, check_crcs, &header)) return false;
  // Up to the image data: ancillary chunks only (they do not change the samples).
  do {
    if (!chunks.next(&chunk)) return false;
    if (chunk.critical() && !chunk.is("IDAT")) return false;
  } while (!chunk.is("IDAT"));

  const SampleType type = header.bit_depth == 16 ? SampleType::u16 : SampleType::u8;
  // Rows of 64 MiB or more go to libpng, row by row: they would need a buffer of two rows here,
  // and zlib counts in 32 bits.
  if (std::size_t{header.width} * sample_bytes(type) >= kInflateBytes * 1024) return false;
  unsigned char* slice = destination(header.width, header.height, type);
  // Per thread, so that the workers of a slab-parallel run decode side by side without
  // allocating a buffer a slice.
  thread_local std::vector<unsigned char> rows;
  // Given back on the way out, however it ends, when a wide image made it large.
  struct Trim {
    std::vector<unsigned char>& rows;
    ~Trim() {
      if (rows.capacity() > kKeptBytes) std::vector<unsigned char>().swap(rows);
    }
  } trim{rows};
  RowInflater inflater(header, slice, rows);
  do {
    if ((check_crcs && !chunk.crc_ok()) || !inflater.feed(chunk.data, chunk.length)) return false;
    if (!chunks.next(&chunk)) return false;
  } while (chunk.is("IDAT"));
  if (!inflater.finish()) return false;
  // After the image data: ancillary chunks, then IEND.
  for (;;) {
    if (chunk.is("IEND")) return chunk.length == 0 && (!check_crcs || chunk.crc_ok());
    if (chunk.critical() || !chunks.next(&chunk)) return false;
  }
}

}  // namespace mvox
