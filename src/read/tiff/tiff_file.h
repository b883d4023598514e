#pragma once
// One open TIFF file, read through the TIFF module (modules/tiff_codecs/tiff_codecs_api.h),
// which is loaded at the first file opened: libtiff and its codec libraries cost every process
// that links them about a millisecond of start-up, so only runs that decode TIFF data only
// libtiff decodes load them (tiff_stack_source.h).
// A TiffFile is used by one thread at a time.
#include <cstdint>
#include <string>

#include "modules/tiff_codecs/tiff_codecs_api.h"

namespace mvox {

struct TiffCodecsApi;  // the module's functions (tiff_file.cpp)

class TiffFile {
 public:
  // Opens `path` at its first page. Throws mvox::Error naming the file when it does not exist,
  // cannot be read as TIFF, or the TIFF module cannot be loaded (naming the module and what
  // installs libtiff).
  explicit TiffFile(const std::string& path);
  ~TiffFile();
  TiffFile(const TiffFile&) = delete;
  TiffFile& operator=(const TiffFile&) = delete;

  const std::string& path() const { return path_; }

  // " (libtiff: MESSAGE)" for the first error libtiff reported since the last call, or "" when
  // it reported none; forgets it.
  std::string take_error();

  // Moves to the next page: false after the last one or when its directory cannot be read
  // (then take_error() says why).
  bool read_directory();
  // Moves to the page whose directory is at byte `offset`: false when it cannot be read.
  bool read_directory_at(std::uint64_t offset);
  mvox_tiff_page tags();
  // The stored place of strip or tile `index` of the current page; false when unknown.
  bool chunk_location(std::uint32_t index, std::uint64_t* offset, std::uint64_t* bytes);
  // Strip or tile `index` decoded into out[0, bytes): true when it filled exactly that.
  bool read_chunk(std::uint32_t index, unsigned char* out, std::uint64_t bytes);
  // Decodes stored bytes (in stored bit order) as read_chunk would.
  bool decode_stored_chunk(std::uint32_t index, unsigned char* stored, std::uint64_t stored_bytes,
                           unsigned char* out, std::uint64_t out_bytes);
  // libtiff inflates this page's deflate data with zlib, not libdeflate (see the API).
  bool inflate_with_zlib();

 private:
  std::string path_;
  const TiffCodecsApi* api_;
  mvox_tiff* handle_ = nullptr;
};

// Loads the TIFF module now, if it is not loaded yet: "" when it is, otherwise the one-line
// reason. For programs that must not take a missing module for a refused file (the fuzzer).
std::string load_tiff_module();

// True when the TIFF module's libtiff decodes TIFF's Compression value `compression`. Loads the
// module; throws mvox::Error(subject, ...) as TiffFile does when it cannot.
bool tiff_codec_configured(std::uint16_t compression, const std::string& subject);

}  // namespace mvox
