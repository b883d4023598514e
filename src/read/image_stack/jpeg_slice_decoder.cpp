#include "read/image_stack/jpeg_slice_decoder.h"

// jpeglib.h uses FILE and size_t without including their headers.
#include <csetjmp>
#include <cstdio>
// clang-format off
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include <new>

#include "error.h"
#include "read/compression_bounds.h"

namespace mvox {
namespace {

// libjpeg's error manager, plus where to jump back to and what went wrong. libjpeg calls
// error_exit for an error and emit_message(-1) for a warning (damaged data it would paper
// over); both end the decoding here: the message is formatted while libjpeg's msg_code and
// parameters still describe it, then longjmp returns to the step that called libjpeg.
struct StrictErrors {
  jpeg_error_mgr manager;  // first, so that libjpeg's pointer to it is a pointer to this
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  int code;
};

[[noreturn]] void stop(j_common_ptr info) {
  auto* errors = reinterpret_cast<StrictErrors*>(info->err);
  errors->code = errors->manager.msg_code;
  errors->manager.format_message(info, errors->message);
  std::longjmp(errors->jump, 1);
}

void on_message(j_common_ptr info, int level) {
  if (level < 0) stop(info);
  // Levels 0 and up are trace messages, which libjpeg would print only above its trace level
  // (0): dropped, like everything else libjpeg would print.
}

void print_nothing(j_common_ptr) {}

// The steps that call libjpeg. Each returns false when libjpeg stopped (StrictErrors says why).
// setjmp/longjmp instead of exceptions, which may not cross libjpeg's C frames: between each
// setjmp here and the longjmp in stop() there are only libjpeg's frames and these, whose
// locals are all trivial, so the jump skips no destructor.

bool create(jpeg_decompress_struct* info, StrictErrors* errors) {
  if (setjmp(errors->jump) != 0) return false;
  jpeg_create_decompress(info);
  return true;
}

bool read_header(jpeg_decompress_struct* info, StrictErrors* errors, const unsigned char* bytes,
                 std::size_t size) {
  if (setjmp(errors->jump) != 0) return false;
  jpeg_mem_src(info, bytes, static_cast<unsigned long>(size));
  jpeg_read_header(info, TRUE);
  return true;
}

// Decodes every row into `samples` (output_width bytes per row), then reads on to the
// end-of-image marker, so that damage after the last row is found too.
bool decode_rows(jpeg_decompress_struct* info, StrictErrors* errors, unsigned char* samples) {
  if (setjmp(errors->jump) != 0) return false;
  jpeg_start_decompress(info);
  while (info->output_scanline < info->output_height) {
    JSAMPROW row = samples + std::size_t{info->output_scanline} * info->output_width;
    jpeg_read_scanlines(info, &row, 1);
  }
  jpeg_finish_decompress(info);
  return true;
}

std::string size_text(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

bool is_jpeg_file(const unsigned char* bytes, std::size_t size) {
  return size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff;
}

void decode_jpeg_slice(const std::string& path, const unsigned char* bytes, std::size_t size,
                       const JpegDestination& destination) {
  StrictErrors errors{};
  jpeg_decompress_struct info{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = stop;
  errors.manager.emit_message = on_message;
  errors.manager.output_message = print_nothing;
  // On every way out, errors included (libjpeg's state is then whatever it was when it stopped,
  // which jpeg_destroy_decompress accepts, even after a failed create).
  struct Destroy {
    jpeg_decompress_struct* info;
    ~Destroy() { jpeg_destroy_decompress(info); }
  } destroy{&info};
  const auto libjpeg_failure = [&] {
    return Error(path, "cannot decode JPEG: " + std::string(errors.message));
  };

  if (!create(&info, &errors) || !read_header(&info, &errors, bytes, size)) throw libjpeg_failure();
  const std::uint32_t width = info.image_width;
  const std::uint32_t height = info.image_height;
  if (info.num_components != 1) {
    throw Error(path, "colour image (" + std::to_string(info.num_components) +
                          " channels): convert to grayscale first");
  }
  const std::uint64_t samples = std::uint64_t{width} * height;
  // Sequential Huffman coding needs bits for every 8x8 block, so a few bytes cannot declare
  // gigabytes. Progressive and arithmetic coding have no such bound.
  if (!info.progressive_mode && !info.arith_code &&
      !could_decode_to(size, kJpegBaselineMaxRatio, samples)) {
    throw Error(path, "JPEG declares " + size_text(width, height) + " samples, more than its " +
                          std::to_string(size) + " bytes of sequential Huffman data can code");
  }

  unsigned char* rows = nullptr;
  try {
    rows = destination(width, height);
  } catch (const std::bad_alloc&) {
    throw Error(path, "out of memory: cannot allocate " + std::to_string(samples) +
                          " bytes for the " + size_text(width, height) + " slice");
  }
  if (!decode_rows(&info, &errors, rows)) {
    if (errors.code == JERR_OUT_OF_MEMORY) {
      // libjpeg does not say how much it asked for. Its largest request, by far, is the whole
      // image's coefficients for a progressive JPEG, 2 bytes per padded sample; otherwise it
      // holds one row of 8x8 blocks at a time (jpeg_has_multiple_scans would call libjpeg
      // again, which must not happen after it stopped).
      const std::uint64_t padded_width = (std::uint64_t{width} + 7) / 8 * 8;
      const std::uint64_t padded_height = (std::uint64_t{height} + 7) / 8 * 8;
      const std::uint64_t asked =
          info.progressive_mode ? padded_width * padded_height * 2 : padded_width * 8;
      throw Error(path, "out of memory: libjpeg could not allocate its buffers for the " +
                            size_text(width, height) + " image (about " + std::to_string(asked) +
                            " bytes)");
    }
    throw libjpeg_failure();
  }
}

}  // namespace mvox
