#include "read/nrrd/nrrd_file.h"

#include <string_view>

#include "error.h"
#include "read/input_format.h"
#include "read/nrrd/nrrd_header.h"
#include "read/raw_file.h"
#include "read/stored_volume_source.h"

namespace mvox {
namespace {

// NRRD headers are a few KB even with long comments or gradient tables; the limit only keeps a
// file that is not a NRRD from being read whole.
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

// The offset just past `line_count` newlines counted from `offset` in `file`.
std::uint64_t skip_lines(RawFile& file, std::uint64_t offset, std::uint64_t line_count) {
  std::string chunk(64 * 1024, '\0');
  std::uint64_t position = offset;
  std::uint64_t lines = 0;
  while (lines < line_count) {
    if (position >= file.size_bytes()) {
      throw Error(file.name(), "line skip " + std::to_string(line_count) + ": the file has only " +
                                   std::to_string(lines) + " lines after byte " +
                                   std::to_string(offset));
    }
    const std::size_t count = static_cast<std::size_t>(
        std::min<std::uint64_t>(chunk.size(), file.size_bytes() - position));
    file.read_at(position, chunk.data(), count);
    const std::string_view piece(chunk.data(), count);
    for (std::size_t i = 0; i < piece.size(); ++i) {
      if (piece[i] == '\n' && ++lines == line_count) return position + i + 1;
    }
    position += count;
  }
  return position;
}

// A NRRD header ends at its first blank line.
bool has_blank_line(const std::string& text) {
  return text.find("\n\n") != std::string::npos || text.find("\n\r\n") != std::string::npos;
}

}  // namespace

std::unique_ptr<StoredVolumeSource> open_nrrd_volume(const std::string& path) {
  RawFile header_file(path);
  const std::string text = read_file_start(header_file, kMaxHeaderBytes, has_blank_line);
  if (header_file.size_bytes() > text.size() && !has_blank_line(text)) {
    throw Error(path, "no blank line ends the header within its first " +
                          std::to_string(kMaxHeaderBytes) + " bytes");
  }
  const NrrdHeader header = parse_nrrd_header(text, path);

  StoredVolumeData data;
  data.header = path;
  if (header.data_file.empty()) {
    data.path = path;
    data.offset = header.header_bytes;
  } else {
    data.path = resolve_data_file(path, header.data_file);
  }
  if (header.line_skip > 0) {
    RawFile data_file(data.path);
    data.offset = skip_lines(data_file, data.offset, header.line_skip);
  }
  if (header.volume.compression == Compression::none) {
    if (header.byte_skip == -1) {
      data.at_end = true;
    } else {
      data.offset += static_cast<std::uint64_t>(header.byte_skip);
    }
  } else {
    // teem applies the byte skip to the decompressed stream.
    data.skip_decompressed = static_cast<std::uint64_t>(header.byte_skip);
  }
  return std::make_unique<StoredVolumeSource>(header.volume, data);
}

const InputFormat& nrrd_volume_format() {
  static const InputFormat format{
      "NRRD volume",
      [](const InputRequest& request) {
        return claims_headered_volume(request, "NRRD", {".nrrd", ".nhdr"});
      },
      [](const InputRequest& request) {
        return open_headered_volume(request, "NRRD", {".nrrd", ".nhdr"}, open_nrrd_volume);
      }};
  return format;
}

}  // namespace mvox
