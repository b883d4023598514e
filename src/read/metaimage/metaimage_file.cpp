#include "read/metaimage/metaimage_file.h"

#include "read/input_format.h"
#include "read/metaimage/metaimage_header.h"
#include "read/raw_file.h"
#include "read/stored_volume_source.h"

namespace mvox {
namespace {

// MetaImage headers are a few hundred bytes; the limit only keeps a file that is not a
// MetaImage from being read whole.
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

}  // namespace

std::unique_ptr<StoredVolumeSource> open_metaimage_volume(const std::string& path) {
  RawFile header_file(path);
  const MetaImageHeader header =
      parse_metaimage_header(read_file_start(header_file, kMaxHeaderBytes), path);

  StoredVolumeData data;
  data.header = path;
  if (header.data_local) {
    data.path = path;
    data.offset = header.header_bytes;
  } else {
    data.path = resolve_data_file(path, header.data_file);
  }
  if (header.header_size == -1) {
    data.at_end = true;
  } else {
    data.offset += static_cast<std::uint64_t>(header.header_size);
  }
  data.compressed_bytes = header.compressed_bytes;
  return std::make_unique<StoredVolumeSource>(header.volume, data);
}

const InputFormat& metaimage_volume_format() {
  static const InputFormat format{
      "MetaImage volume",
      [](const InputRequest& request) {
        return claims_headered_volume(request, "MetaImage", {".mhd", ".mha"});
      },
      [](const InputRequest& request) {
        return open_headered_volume(request, "MetaImage", {".mhd", ".mha"}, open_metaimage_volume);
      }};
  return format;
}

}  // namespace mvox
