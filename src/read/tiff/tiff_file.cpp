#include "read/tiff/tiff_file.h"

#include <filesystem>

#include "error.h"
#include "modules/module_loader.h"

namespace mvox {

struct TiffCodecsApi {
  decltype(&mvox_tiff_codec_configured) codec_configured = nullptr;
  decltype(&mvox_tiff_open) open = nullptr;
  decltype(&mvox_tiff_close) close = nullptr;
  decltype(&mvox_tiff_take_error) take_error = nullptr;
  decltype(&mvox_tiff_read_directory) read_directory = nullptr;
  decltype(&mvox_tiff_read_directory_at) read_directory_at = nullptr;
  decltype(&mvox_tiff_page_tags) page_tags = nullptr;
  decltype(&mvox_tiff_chunk_location) chunk_location = nullptr;
  decltype(&mvox_tiff_read_chunk) read_chunk = nullptr;
  decltype(&mvox_tiff_decode_stored_chunk) decode_stored_chunk = nullptr;
  decltype(&mvox_tiff_inflate_with_zlib) inflate_with_zlib = nullptr;
};

namespace {

constexpr ModuleName kTiffCodecs{
    "libmvox_tiff_codecs.so", "TIFF module (libtiff)",
    "libtiff (apt-get install libtiff-dev; scripts/install_deps.sh installs it)"};

// The module's functions, loaded at the first use; or mvox::Error(subject, why not).
const TiffCodecsApi& api(const std::string& subject) {
  return module_functions<TiffCodecsApi>(
      kTiffCodecs, "mvox_tiff_codecs_api_version", MVOX_TIFF_CODECS_API_VERSION, subject,
      [&](void* handle, TiffCodecsApi& f) {
        auto resolve = [&](const char* symbol, auto** function) {
          resolve_function(handle, symbol, function, kTiffCodecs, subject);
        };
        resolve("mvox_tiff_codec_configured", &f.codec_configured);
        resolve("mvox_tiff_open", &f.open);
        resolve("mvox_tiff_close", &f.close);
        resolve("mvox_tiff_take_error", &f.take_error);
        resolve("mvox_tiff_read_directory", &f.read_directory);
        resolve("mvox_tiff_read_directory_at", &f.read_directory_at);
        resolve("mvox_tiff_page_tags", &f.page_tags);
        resolve("mvox_tiff_chunk_location", &f.chunk_location);
        resolve("mvox_tiff_read_chunk", &f.read_chunk);
        resolve("mvox_tiff_decode_stored_chunk", &f.decode_stored_chunk);
        resolve("mvox_tiff_inflate_with_zlib", &f.inflate_with_zlib);
      });
}

}  // namespace

std::string load_tiff_module() {
  try {
    api("TIFF");
    return "";
  } catch (const Error& error) {
    return error.what();
  }
}

bool tiff_codec_configured(std::uint16_t compression, const std::string& subject) {
  return api(subject).codec_configured(compression) != 0;
}

TiffFile::TiffFile(const std::string& path) : path_(path), api_(nullptr) {
  std::error_code ignored;
  if (!std::filesystem::exists(path_, ignored)) throw Error(path_, "no such file");
  api_ = &api(path_);
  char error[512] = "";
  handle_ = api_->open(path_.c_str(), error, sizeof error);
  if (!handle_) {
    const std::string said = error[0] == '\0' ? "" : " (libtiff: " + std::string(error) + ")";
    throw Error(path_, "cannot read as TIFF (unreadable, corrupt, truncated or not a TIFF)" + said);
  }
}

TiffFile::~TiffFile() {
  if (handle_) api_->close(handle_);
}

std::string TiffFile::take_error() {
  char error[512] = "";
  api_->take_error(handle_, error, sizeof error);
  return error[0] == '\0' ? "" : " (libtiff: " + std::string(error) + ")";
}

bool TiffFile::read_directory() { return api_->read_directory(handle_) != 0; }

bool TiffFile::read_directory_at(std::uint64_t offset) {
  return api_->read_directory_at(handle_, offset) != 0;
}

mvox_tiff_page TiffFile::tags() {
  mvox_tiff_page page;
  api_->page_tags(handle_, &page);
  return page;
}

bool TiffFile::chunk_location(std::uint32_t index, std::uint64_t* offset, std::uint64_t* bytes) {
  return api_->chunk_location(handle_, index, offset, bytes) != 0;
}

bool TiffFile::read_chunk(std::uint32_t index, unsigned char* out, std::uint64_t bytes) {
  return api_->read_chunk(handle_, index, out, static_cast<std::int64_t>(bytes)) ==
         static_cast<std::int64_t>(bytes);
}

bool TiffFile::decode_stored_chunk(std::uint32_t index, unsigned char* stored,
                                   std::uint64_t stored_bytes, unsigned char* out,
                                   std::uint64_t out_bytes) {
  return api_->decode_stored_chunk(handle_, index, stored, static_cast<std::int64_t>(stored_bytes),
                                   out, static_cast<std::int64_t>(out_bytes)) != 0;
}

bool TiffFile::inflate_with_zlib() { return api_->inflate_with_zlib(handle_) != 0; }

}  // namespace mvox
