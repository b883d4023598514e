#include "read/dicom/dicom_codestream.h"

#include <cstdint>

#include "read/compression_bounds.h"
#include "read/dicom/dicom_header.h"

namespace mvox {
namespace {

enum class Codec { unchecked, jpeg, jpeg2000, rle };

Codec codec_of(const std::string& uid) {
  if (uid == "1.2.840.10008.1.2.5") return Codec::rle;
  const std::string jpeg_family = "1.2.840.10008.1.2.4.";
  if (uid.compare(0, jpeg_family.size(), jpeg_family) != 0) return Codec::unchecked;
  const std::string number = uid.substr(jpeg_family.size());
  if (number.empty() || number.size() > 3 ||
      number.find_first_not_of("0123456789") != std::string::npos)
    return Codec::unchecked;
  const int n = std::stoi(number);
  // 50 .. 70: the JPEG processes (most retired, all with the same markers); 80, 81: JPEG-LS,
  // whose markers follow JPEG's; 90 .. 93: JPEG 2000.
  if ((n >= 50 && n <= 70) || n == 80 || n == 81) return Codec::jpeg;
  if (n >= 90 && n <= 93) return Codec::jpeg2000;
  return Codec::unchecked;
}

std::uint8_t byte(const std::string& s, std::size_t i) { return static_cast<std::uint8_t>(s[i]); }
std::uint32_t be16(const std::string& s, std::size_t i) { return byte(s, i) << 8 | byte(s, i + 1); }
std::uint32_t be32(const std::string& s, std::size_t i) {
  return be16(s, i) << 16 | be16(s, i + 2);
}
std::uint32_t le32(const std::string& s, std::size_t i) {
  return std::uint32_t{byte(s, i + 3)} << 24 | std::uint32_t{byte(s, i + 2)} << 16 |
         std::uint32_t{byte(s, i + 1)} << 8 | byte(s, i);
}

std::string size_text(std::uint64_t columns, std::uint64_t rows) {
  return std::to_string(columns) + "x" + std::to_string(rows);
}

// The codestream's image against the header's; "" when they agree.
std::string image_problem(const char* codec, std::uint64_t columns, std::uint64_t rows,
                          unsigned components, unsigned precision, const DicomImageHeader& h) {
  if (columns != h.columns || rows != h.rows)
    return std::string("its ") + codec + " codestream is " + size_text(columns, rows) +
           ", the DICOM header says " + size_text(h.columns, h.rows);
  if (components != 1)
    return std::string("its ") + codec + " codestream has " + std::to_string(components) +
           " components, the DICOM header says 1";
  if (precision == 0 || precision > h.bits_allocated)
    return std::string("its ") + codec + " codestream has " + std::to_string(precision) +
           "-bit samples, the DICOM header allocates " + std::to_string(h.bits_allocated);
  return {};
}

// JPEG and JPEG-LS: SOI, then segments up to the frame header (SOFn, or SOF55 for JPEG-LS).
std::string jpeg_header_problem(const std::string& head, const DicomImageHeader& h) {
  if (head.size() < 2 || byte(head, 0) != 0xFF || byte(head, 1) != 0xD8)
    return "its JPEG codestream does not start with SOI (FFD8)";
  std::size_t at = 2;
  while (at < head.size()) {
    if (byte(head, at) != 0xFF) return {};  // not a marker: left to the decoder to refuse
    while (at < head.size() && byte(head, at) == 0xFF) ++at;  // fill bytes
    if (at >= head.size()) return {};
    const std::uint8_t marker = byte(head, at++);
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;  // no length
    if (marker == 0xD9 || marker == 0xDA)
      return "its JPEG codestream has no frame header (SOF) before its scan";
    if (at + 2 > head.size()) return {};
    const std::uint32_t length = be16(head, at);
    if (length < 2) return "its JPEG codestream has a segment of length " + std::to_string(length);
    const bool frame_header =
        (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) ||
        marker == 0xF7;  // SOF55, JPEG-LS
    if (frame_header) {
      if (length < 8 || at + 8 > head.size()) return {};
      return image_problem(marker == 0xF7 ? "JPEG-LS" : "JPEG", be16(head, at + 5),
                           be16(head, at + 3), byte(head, at + 7), byte(head, at + 2), h);
    }
    at += length;
  }
  return {};  // the frame header lies beyond the bytes kept: the decoder checks it
}

// JPEG 2000: SOC, then SIZ (ISO 15444-1 A.5.1), possibly inside a JP2 file's boxes.
std::string jpeg2000_header_problem(const std::string& head, const DicomImageHeader& h) {
  std::size_t at = 0;
  const std::string jp2_signature("\x00\x00\x00\x0C\x6A\x50\x20\x20", 8);
  if (head.compare(0, jp2_signature.size(), jp2_signature) == 0) {
    at = head.find(std::string("\xFF\x4F\xFF\x51", 4));
    if (at == std::string::npos) return {};  // deeper in the file than the bytes kept
  }
  if (head.size() < at + 45 || be16(head, at) != 0xFF4F || be16(head, at + 2) != 0xFF51)
    return "its JPEG 2000 codestream does not start with SOC and SIZ (FF4F FF51)";
  const std::uint32_t width = be32(head, at + 8), height = be32(head, at + 12);
  const std::uint32_t x_offset = be32(head, at + 16), y_offset = be32(head, at + 20);
  if (x_offset > width || y_offset > height)
    return "its JPEG 2000 codestream has an image offset beyond its size";
  const unsigned components = be16(head, at + 40);
  const unsigned precision = (byte(head, at + 42) & 0x7F) + 1u;
  if (components == 1 && (byte(head, at + 43) != 1 || byte(head, at + 44) != 1))
    return "its JPEG 2000 codestream is subsampled";
  return image_problem("JPEG 2000", width - x_offset, height - y_offset, components, precision, h);
}

// JPEG and JPEG 2000 codestreams end with FFD9 (EOI, EOC); DICOM pads fragments to an even
// length with a zero.
std::string end_problem(const std::string& tail, const char* codec) {
  std::size_t end = tail.size();
  while (end > 0 && tail[end - 1] == '\0') --end;
  if (end < 2 || byte(tail, end - 2) != 0xFF || byte(tail, end - 1) != 0xD9)
    return std::string("its ") + codec + " codestream does not end with FFD9 (cut short?)";
  return {};
}

// RLE (PS3.5 G.3.1): 16 little-endian 32-bit numbers: the segment count, then their offsets.
std::string rle_problem(const DicomFragment& fragment, const DicomImageHeader& h) {
  if (fragment.head.size() < 64) return "its RLE fragment is shorter than the 64-byte RLE header";
  const std::uint32_t segments = le32(fragment.head, 0);
  if (segments != h.bits_allocated / 8u)
    return "its RLE header has " + std::to_string(segments) + " segments, " +
           std::to_string(h.bits_allocated) + "-bit samples need " +
           std::to_string(h.bits_allocated / 8u);
  std::uint64_t previous = 0;
  for (std::uint32_t i = 0; i < segments; ++i) {
    const std::uint32_t offset = le32(fragment.head, 4 + 4 * i);
    if ((i == 0 && offset != 64) || (i > 0 && offset <= previous) || offset >= fragment.length)
      return "its RLE header has segment offsets out of order or beyond the fragment";
    previous = offset;
  }
  return {};
}

}  // namespace

namespace {

// The most a frame's encoded bytes can decode to, per byte, in transfer syntax `uid`, or 0 when
// the codec has no such bound (compression_bounds.h).
std::uint64_t max_expansion(const std::string& uid) {
  if (uid == "1.2.840.10008.1.2.5") return kRleMaxRatio;
  if (uid == "1.2.840.10008.1.2.4.50" || uid == "1.2.840.10008.1.2.4.51")
    return kJpegBaselineMaxRatio;  // baseline and extended sequential DCT
  if (uid == "1.2.840.10008.1.2.4.57" || uid == "1.2.840.10008.1.2.4.70")
    return kJpegLosslessMaxRatio;
  return 0;  // JPEG-LS and JPEG 2000 have run modes without a bound
}

}  // namespace

std::string compressed_pixel_data_problem(const std::vector<DicomFragment>& fragments,
                                          const DicomImageHeader& h) {
  const Codec codec = codec_of(h.transfer_syntax_uid);
  if (codec == Codec::unchecked) return {};
  if (fragments.empty()) return "its compressed pixel data holds no fragment";
  // Each frame: its first and its last fragment.
  std::vector<std::pair<const DicomFragment*, const DicomFragment*>> frames;
  if (fragments.size() == h.frames) {
    for (const DicomFragment& f : fragments) frames.emplace_back(&f, &f);
  } else if (h.frames == 1 && codec != Codec::rle) {
    frames.emplace_back(&fragments.front(), &fragments.back());
  } else {
    return "its compressed pixel data has " + std::to_string(fragments.size()) + " fragments for " +
           std::to_string(h.frames) +
           " frames; mvox reads one fragment per frame, or one frame in several";
  }
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const DicomFragment& first = *frames[k].first;
    const DicomFragment& last = *frames[k].second;
    std::string problem;
    // A header that declares more than the frame's bytes can decode to: refused before GDCM
    // allocates for it.
    std::uint64_t encoded = 0;
    for (const DicomFragment* f = &first; f <= &last; ++f) encoded += f->length;
    if (const std::uint64_t ratio = max_expansion(h.transfer_syntax_uid);
        ratio != 0 && !could_decode_to(encoded, ratio, dicom_frame_bytes(h))) {
      problem = "its " + std::to_string(encoded) + " bytes of compressed data cannot hold a " +
                std::to_string(h.columns) + "x" + std::to_string(h.rows) + " frame of " +
                std::to_string(dicom_frame_bytes(h)) + " bytes (this codec expands at most " +
                std::to_string(ratio) + " to 1)";
      return h.frames > 1 ? "frame " + std::to_string(k + 1) + ": " + problem : problem;
    }
    switch (codec) {
      case Codec::jpeg:
        problem = jpeg_header_problem(first.head, h);
        if (problem.empty()) problem = end_problem(last.tail, "JPEG");
        break;
      case Codec::jpeg2000:
        problem = jpeg2000_header_problem(first.head, h);
        if (problem.empty()) problem = end_problem(last.tail, "JPEG 2000");
        break;
      case Codec::rle: problem = rle_problem(first, h); break;
      case Codec::unchecked: break;
    }
    if (!problem.empty())
      return h.frames > 1 ? "frame " + std::to_string(k + 1) + ": " + problem : problem;
  }
  return {};
}

}  // namespace mvox
