#include "tiff_bytes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>

#include "deflate.h"

namespace mvox::test {
namespace {

void put_u16(std::vector<unsigned char>& out, std::size_t at, std::uint32_t value) {
  out[at] = static_cast<unsigned char>(value);
  out[at + 1] = static_cast<unsigned char>(value >> 8);
}

void put_u32(std::vector<unsigned char>& out, std::size_t at, std::uint32_t value) {
  put_u16(out, at, value & 0xffff);
  put_u16(out, at + 2, value >> 16);
}

void append_u16(std::vector<unsigned char>& out, std::uint32_t value) {
  out.resize(out.size() + 2);
  put_u16(out, out.size() - 2, value);
}

void append_u32(std::vector<unsigned char>& out, std::uint32_t value) {
  out.resize(out.size() + 4);
  put_u32(out, out.size() - 4, value);
}

constexpr std::uint16_t kShort = 3;
constexpr std::uint16_t kLong = 4;

struct Entry {
  std::uint16_t tag;
  std::uint16_t type;
  std::vector<std::uint32_t> values;
};

}  // namespace

std::vector<unsigned char> tiff_file_bytes(const std::vector<TiffPageBytes>& pages) {
  std::vector<unsigned char> out = {'I', 'I', 42, 0, 0, 0, 0, 0};
  std::size_t link = 4;  // where the offset of the next directory goes
  for (const TiffPageBytes& page : pages) {
    std::vector<std::uint32_t> offsets, counts;
    for (const std::vector<unsigned char>& chunk : page.chunks) {
      offsets.push_back(static_cast<std::uint32_t>(out.size()));
      counts.push_back(static_cast<std::uint32_t>(chunk.size()));
      out.insert(out.end(), chunk.begin(), chunk.end());
      if (out.size() % 2) out.push_back(0);
    }
    const bool tiled = page.tile_width != 0 && page.tile_height != 0;
    std::vector<Entry> entries = {{256, kLong, {page.width}},
                                  {257, kLong, {page.height}},
                                  {258, kShort, {page.bits}},
                                  {259, kShort, {page.compression}},
                                  {262, kShort, {1}}};
    if (!tiled) {
      entries.push_back({273, kLong, offsets});
      entries.push_back({277, kShort, {1}});
      entries.push_back({278, kLong, {page.rows_per_strip ? page.rows_per_strip : page.height}});
      entries.push_back({279, kLong, counts});
    } else {
      entries.push_back({277, kShort, {1}});
      entries.push_back({322, kLong, {page.tile_width}});
      entries.push_back({323, kLong, {page.tile_height}});
      entries.push_back({324, kLong, offsets});
      entries.push_back({325, kLong, counts});
    }
    // Values that do not fit in an entry's 4 bytes go before the directory.
    std::vector<std::uint32_t> value_offsets;
    for (const Entry& entry : entries) {
      const std::size_t size = entry.values.size() * (entry.type == kShort ? 2 : 4);
      value_offsets.push_back(static_cast<std::uint32_t>(out.size()));
      if (size <= 4) continue;
      for (std::uint32_t value : entry.values)
        entry.type == kShort ? append_u16(out, value) : append_u32(out, value);
    }
    put_u32(out, link, static_cast<std::uint32_t>(out.size()));
    append_u16(out, static_cast<std::uint32_t>(entries.size()));
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const Entry& entry = entries[i];
      append_u16(out, entry.tag);
      append_u16(out, entry.type);
      append_u32(out, static_cast<std::uint32_t>(entry.values.size()));
      const std::size_t size = entry.values.size() * (entry.type == kShort ? 2 : 4);
      if (size > 4) {
        append_u32(out, value_offsets[i]);
      } else if (entry.type == kShort) {
        append_u16(out, entry.values.empty() ? 0 : entry.values[0]);
        append_u16(out, entry.values.size() > 1 ? entry.values[1] : 0);
      } else {
        append_u32(out, entry.values.empty() ? 0 : entry.values[0]);
      }
    }
    link = out.size();
    append_u32(out, 0);
  }
  return out;
}

std::vector<unsigned char> zlib_compressed(const std::vector<unsigned char>& bytes) {
  return deflate_bytes(bytes, false);
}

namespace {

std::uint32_t u16_at(const std::vector<unsigned char>& bytes, std::size_t at) {
  return bytes.at(at) | std::uint32_t{bytes.at(at + 1)} << 8;
}

std::uint32_t u32_at(const std::vector<unsigned char>& bytes, std::size_t at) {
  return u16_at(bytes, at) | u16_at(bytes, at + 2) << 16;
}

}  // namespace

void put_tiff_u16(std::vector<unsigned char>& bytes, std::size_t at, std::uint32_t value) {
  put_u16(bytes, at, value);
}

void put_tiff_u32(std::vector<unsigned char>& bytes, std::size_t at, std::uint32_t value) {
  put_u32(bytes, at, value);
}

std::uint32_t tiff_directory_offset(const std::vector<unsigned char>& bytes, int page) {
  std::uint32_t offset = u32_at(bytes, 4);
  for (int i = 0; i < page; ++i) offset = u32_at(bytes, offset + 2 + 12 * u16_at(bytes, offset));
  return offset;
}

std::size_t tiff_next_link(const std::vector<unsigned char>& bytes, int page) {
  const std::uint32_t offset = tiff_directory_offset(bytes, page);
  return offset + 2 + 12 * u16_at(bytes, offset);
}

std::size_t tiff_entry_offset(const std::vector<unsigned char>& bytes, int page,
                              std::uint16_t tag) {
  const std::uint32_t offset = tiff_directory_offset(bytes, page);
  for (std::uint32_t i = 0; i < u16_at(bytes, offset); ++i) {
    const std::size_t entry = offset + 2 + 12 * i;
    if (u16_at(bytes, entry) == tag) return entry;
  }
  ADD_FAILURE() << "no tag " << tag << " in directory " << page;
  return 0;
}

void rename_tiff_tag(std::vector<unsigned char>& bytes, int page, std::uint16_t tag,
                     std::uint16_t new_tag) {
  put_u16(bytes, tiff_entry_offset(bytes, page, tag), new_tag);
}

std::vector<TiffPageBytes> tiff_pages_of(const std::string& samples, std::uint32_t width,
                                         std::uint32_t height, std::uint32_t first,
                                         std::uint32_t count, bool deflate,
                                         std::uint32_t rows_per_strip) {
  std::vector<TiffPageBytes> pages;
  const std::size_t slice = std::size_t{width} * height;
  const std::uint32_t rows = rows_per_strip == 0 ? height : rows_per_strip;
  for (std::uint32_t z = first; z < first + count; ++z) {
    TiffPageBytes page{width, height, 8, std::uint16_t(deflate ? 8 : 1), rows, 0, 0, {}};
    for (std::uint32_t y = 0; y < height; y += rows) {
      const std::size_t at = z * slice + std::size_t{y} * width;
      const std::size_t bytes = std::size_t{width} * std::min(rows, height - y);
      std::vector<unsigned char> strip(samples.begin() + at, samples.begin() + at + bytes);
      page.chunks.push_back(deflate ? zlib_compressed(strip) : strip);
    }
    pages.push_back(page);
  }
  return pages;
}

}  // namespace mvox::test
