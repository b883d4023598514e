#include "read/dicom/dicom_file_scan.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "error.h"
#include "read/file_names.h"

namespace mvox {
namespace {

constexpr std::uint32_t kItem = dicom_tag(0xFFFE, 0xE000);
constexpr std::uint32_t kItemDelimiter = dicom_tag(0xFFFE, 0xE00D);
constexpr std::uint32_t kSequenceDelimiter = dicom_tag(0xFFFE, 0xE0DD);
constexpr std::uint32_t kPixelData = dicom_tag(0x7FE0, 0x0010);
constexpr std::uint32_t kMediaStorageSopClassUid = dicom_tag(0x0002, 0x0002);
constexpr std::uint32_t kTransferSyntaxUid = dicom_tag(0x0002, 0x0010);
constexpr std::uint32_t kUndefinedLength = 0xFFFFFFFF;
constexpr std::uint64_t kNoEnd = ~std::uint64_t{0};
constexpr int kMaxDepth = 32;
// Values kept for the caller are short (UIDs, numbers, codes); a longer one is not what we want.
constexpr std::uint32_t kMaxKeptValueBytes = 1024;

constexpr const char* kImplicitLittleEndian = "1.2.840.10008.1.2";
constexpr const char* kExplicitLittleEndian = "1.2.840.10008.1.2.1";
constexpr const char* kExplicitBigEndian = "1.2.840.10008.1.2.2";
constexpr const char* kDeflatedLittleEndian = "1.2.840.10008.1.2.1.99";

// Thrown inside the walk; scan_dicom_file turns it into an Error or "not DICOM".
struct Malformed {
  std::string problem;
  bool truncated = false;  // the file ends too early, rather than holding wrong bytes
};

// A read-only file with an exact position and size, so that every length can be checked against
// what is left before anything is read or skipped. Reads go through a window of the file, so that
// the walk's many small reads, peeks and skips over short values cost no system call; only a
// skip past the window (over pixel data) makes the next read fetch another.
class FileBytes {
 public:
  // Files are listed as regular files and read later (a series' slices, each at its turn):
  // one replaced by a FIFO meanwhile is refused rather than waited for (O_NONBLOCK), as image
  // stacks refuse theirs (file_bytes.h).
  explicit FileBytes(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw Error(path, "cannot open file: " + errno_text(errno));
    struct stat status {};
    if (::fstat(fd, &status) != 0) {
      const int error_number = errno;
      ::close(fd);
      throw Error(path, "cannot read file size: " + errno_text(error_number));
    }
    if (!S_ISREG(status.st_mode)) {
      ::close(fd);
      throw Error(path, "is no longer a regular file");
    }
    // Regular: O_NONBLOCK changes nothing for its reads.
    file_ = ::fdopen(fd, "rb");
    if (!file_) {
      const int error_number = errno;
      ::close(fd);
      throw Error(path, "cannot open file: " + errno_text(error_number));
    }
    size_ = static_cast<std::uint64_t>(status.st_size);
  }
  ~FileBytes() { std::fclose(file_); }
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;

  std::uint64_t size() const { return size_; }
  std::uint64_t position() const { return position_; }
  std::uint64_t left() const { return size_ - position_; }

  bool read(void* destination, std::size_t count) {
    if (count > left()) return false;
    auto* out = static_cast<unsigned char*>(destination);
    while (count > 0) {
      if (position_ < window_start_ || position_ >= window_start_ + window_bytes_) {
        if (!fill()) return false;
      }
      const std::size_t offset = static_cast<std::size_t>(position_ - window_start_);
      const std::size_t chunk = std::min(count, window_bytes_ - offset);
      std::memcpy(out, window_.data() + offset, chunk);
      out += chunk;
      count -= chunk;
      position_ += chunk;
    }
    return true;
  }
  bool seek(std::uint64_t position) {
    if (position > size_) return false;
    position_ = position;
    return true;
  }

 private:
  // Loads the window starting at position_.
  bool fill() {
    if (fseeko(file_, static_cast<off_t>(position_), SEEK_SET) != 0) return false;
    window_bytes_ = std::fread(window_.data(), 1, window_.size(), file_);
    window_start_ = position_;
    return window_bytes_ > 0;
  }

  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0;
  std::uint64_t position_ = 0;
  std::vector<unsigned char> window_ = std::vector<unsigned char>(64 * 1024);
  std::uint64_t window_start_ = 0;
  std::size_t window_bytes_ = 0;
};

struct Encoding {
  bool explicit_vr = true;
  bool big_endian = false;
};

bool is_vr_letter(unsigned char c) { return c >= 'A' && c <= 'Z'; }

// The VRs of PS3.5 Table 6.2-1. GDCM asserts on any other in the file meta group, so the walk
// accepts no other anywhere.
bool is_known_vr(const char vr[2]) {
  static const char* const kKnown[] = {"AE", "AS", "AT", "CS", "DA", "DS", "DT", "FD", "FL",
                                       "IS", "LO", "LT", "OB", "OD", "OF", "OL", "OV", "OW",
                                       "PN", "SH", "SL", "SQ", "SS", "ST", "SV", "TM", "UC",
                                       "UI", "UL", "UN", "UR", "US", "UT", "UV"};
  return std::any_of(std::begin(kKnown), std::end(kKnown),
                     [&](const char* v) { return vr[0] == v[0] && vr[1] == v[1]; });
}

// Elements GDCM reads through gdcm::Attribute, which asserts that the VR is the standard's, and
// (for binary VRs) that the value has the right length. A file that breaks this is refused here.
struct ExpectedElement {
  std::uint32_t tag;
  char vr[3];
  std::uint32_t length;  // 0: any
};
constexpr ExpectedElement kExpectedElements[] = {
    {dicom_tag(0x0002, 0x0000), "UL", 4}, {dicom_tag(0x0002, 0x0001), "OB", 0},
    {dicom_tag(0x0002, 0x0002), "UI", 0}, {dicom_tag(0x0002, 0x0003), "UI", 0},
    {dicom_tag(0x0002, 0x0010), "UI", 0}, {dicom_tag(0x0002, 0x0012), "UI", 0},
    {dicom_tag(0x0002, 0x0013), "SH", 0}, {dicom_tag(0x0002, 0x0016), "AE", 0},
    {dicom_tag(0x0008, 0x0008), "CS", 0}, {dicom_tag(0x0008, 0x0010), "SH", 0},
    {dicom_tag(0x0008, 0x0016), "UI", 0}, {dicom_tag(0x0008, 0x0018), "UI", 0},
    {dicom_tag(0x0008, 0x0060), "CS", 0}, {dicom_tag(0x0018, 0x0050), "DS", 0},
    {dicom_tag(0x0018, 0x0088), "DS", 0}, {dicom_tag(0x0020, 0x000D), "UI", 0},
    {dicom_tag(0x0020, 0x000E), "UI", 0}, {dicom_tag(0x0020, 0x0013), "IS", 0},
    {dicom_tag(0x0020, 0x0032), "DS", 0}, {dicom_tag(0x0020, 0x0037), "DS", 0},
    {dicom_tag(0x0028, 0x0002), "US", 2}, {dicom_tag(0x0028, 0x0004), "CS", 0},
    {dicom_tag(0x0028, 0x0006), "US", 2}, {dicom_tag(0x0028, 0x0008), "IS", 0},
    {dicom_tag(0x0028, 0x0010), "US", 2}, {dicom_tag(0x0028, 0x0011), "US", 2},
    {dicom_tag(0x0028, 0x0030), "DS", 0}, {dicom_tag(0x0028, 0x0034), "IS", 0},
    {dicom_tag(0x0028, 0x0100), "US", 2}, {dicom_tag(0x0028, 0x0101), "US", 2},
    {dicom_tag(0x0028, 0x0102), "US", 2}, {dicom_tag(0x0028, 0x0103), "US", 2},
    {dicom_tag(0x0028, 0x1050), "DS", 0}, {dicom_tag(0x0028, 0x1051), "DS", 0},
    {dicom_tag(0x0028, 0x1052), "DS", 0}, {dicom_tag(0x0028, 0x1053), "DS", 0},
    {dicom_tag(0x0028, 0x1054), "LO", 0},
};
constexpr std::uint32_t kRecognitionCode = dicom_tag(0x0008, 0x0010);

const ExpectedElement* expected_element(std::uint32_t tag) {
  for (const ExpectedElement& e : kExpectedElements)
    if (e.tag == tag) return &e;
  return nullptr;
}

// VRs whose explicit encoding has two reserved bytes and a 32-bit length (PS3.5 7.1.2).
bool has_long_length(const char vr[2]) {
  static const char* const kLong[] = {"OB", "OD", "OF", "OL", "OV", "OW", "SQ",
                                      "SV", "UC", "UN", "UR", "UT", "UV"};
  return std::any_of(std::begin(kLong), std::end(kLong),
                     [&](const char* v) { return vr[0] == v[0] && vr[1] == v[1]; });
}

class Walker {
 public:
  Walker(FileBytes& file, const std::uint32_t* wanted, std::size_t wanted_count,
         DicomFileScan& scan)
      : file_(file), wanted_(wanted), wanted_count_(wanted_count), scan_(scan) {}

  // The file meta group: explicit VR little endian whatever the transfer syntax (PS3.10 7.1).
  void meta_group() {
    const Encoding meta{true, false};
    while (peek_group(meta) == 0x0002) {
      const Header h = header(meta);
      if (h.length == kUndefinedLength) fail(h, "has an undefined length in the file meta group");
      need(h, h.length);
      check_expected(h, meta);
      if ((h.tag == kTransferSyntaxUid || h.tag == kMediaStorageSopClassUid) &&
          h.length <= kMaxKeptValueBytes) {
        std::string uid(h.length, '\0');
        if (!file_.read(uid.data(), uid.size())) fail(h, "cannot be read");
        while (!uid.empty() && (uid.back() == '\0' || uid.back() == ' ')) uid.pop_back();
        (h.tag == kTransferSyntaxUid ? scan_.transfer_syntax_uid
                                     : scan_.media_storage_sop_class_uid) = uid;
      } else {
        skip(h, h.length);
      }
    }
  }

  // The main data set, from here to the end of the file.
  void data_set(Encoding encoding) { elements(encoding, kNoEnd, 0, false); }

  // Reads the first bytes of a data set without a meta group and says how it is encoded, or
  // that it does not look like DICOM at all.
  std::optional<Encoding> guess_bare_encoding() {
    unsigned char bytes[8];
    const std::uint64_t start = file_.position();
    if (!file_.read(bytes, sizeof bytes)) return std::nullopt;
    file_.seek(start);
    const std::uint16_t group = static_cast<std::uint16_t>(bytes[0] | bytes[1] << 8);
    if (group != 0x0000 && group != 0x0008) return std::nullopt;
    if (is_vr_letter(bytes[4]) && is_vr_letter(bytes[5])) return Encoding{true, false};
    return Encoding{false, false};
  }

  // Some writers declare explicit VR little endian but encode the data set implicitly; GDCM reads
  // those, so the walk follows the first element's bytes rather than the declaration.
  bool next_element_has_vr() {
    unsigned char bytes[6];
    const std::uint64_t start = file_.position();
    if (!file_.read(bytes, sizeof bytes)) return true;
    file_.seek(start);
    return is_vr_letter(bytes[4]) && is_vr_letter(bytes[5]);
  }

 private:
  struct Header {
    std::uint32_t tag = 0;
    char vr[2] = {0, 0};  // explicit VR only
    std::uint32_t length = 0;
    std::uint64_t offset = 0;  // of the element's first byte
  };

  [[noreturn]] void fail(const Header& h, const std::string& problem) {
    throw Malformed{"element " + dicom_tag_text(h.tag) + " at byte " + std::to_string(h.offset) +
                    " " + problem};
  }
  [[noreturn]] void truncated(const Header& h) {
    throw Malformed{"element " + dicom_tag_text(h.tag) + " at byte " + std::to_string(h.offset) +
                        " is cut off by the end of the file (" + std::to_string(file_.size()) +
                        " bytes)",
                    true};
  }

  std::uint16_t u16(const unsigned char* b, const Encoding& e) const {
    return e.big_endian ? static_cast<std::uint16_t>(b[0] << 8 | b[1])
                        : static_cast<std::uint16_t>(b[1] << 8 | b[0]);
  }
  std::uint32_t u32(const unsigned char* b, const Encoding& e) const {
    return e.big_endian ? std::uint32_t{b[0]} << 24 | std::uint32_t{b[1]} << 16 |
                              std::uint32_t{b[2]} << 8 | b[3]
                        : std::uint32_t{b[3]} << 24 | std::uint32_t{b[2]} << 16 |
                              std::uint32_t{b[1]} << 8 | b[0];
  }

  // The group of the next element, or 0xFFFF at the end of the file (no element follows).
  std::uint16_t peek_group(const Encoding& e) {
    unsigned char bytes[2];
    const std::uint64_t start = file_.position();
    if (!file_.read(bytes, 2)) return 0xFFFF;
    file_.seek(start);
    return u16(bytes, e);
  }

  // Reads an element header: tag, VR when explicit, value length. Item tags (FFFE,xxxx) have
  // no VR in any encoding.
  Header header(const Encoding& e) {
    Header h;
    h.offset = file_.position();
    unsigned char bytes[8];
    if (!file_.read(bytes, 4)) {
      h.tag = 0;
      throw Malformed{std::to_string(file_.left()) +
                          " stray bytes where an element should start, at byte " +
                          std::to_string(h.offset),
                      true};
    }
    h.tag = std::uint32_t{u16(bytes, e)} << 16 | u16(bytes + 2, e);
    if ((h.tag >> 16) == 0xFFFE || !e.explicit_vr) {
      if (!file_.read(bytes, 4)) truncated(h);
      h.length = u32(bytes, e);
      return h;
    }
    if (!file_.read(bytes, 4)) truncated(h);
    if (!is_vr_letter(bytes[0]) || !is_vr_letter(bytes[1])) fail(h, "has no valid VR");
    h.vr[0] = static_cast<char>(bytes[0]);
    h.vr[1] = static_cast<char>(bytes[1]);
    if (!is_known_vr(h.vr)) fail(h, std::string("has an unknown VR ") + h.vr[0] + h.vr[1]);
    if (has_long_length(h.vr)) {
      if (!file_.read(bytes, 4)) truncated(h);
      h.length = u32(bytes, e);
    } else {
      h.length = u16(bytes + 2, e);
    }
    return h;
  }

  // The value of `h` must fit before `end` and in the file.
  void need(const Header& h, std::uint64_t length, std::uint64_t end = kNoEnd) {
    if (length > file_.left()) truncated(h);
    if (end != kNoEnd && file_.position() + length > end)
      fail(h, "runs past the end of the item that holds it");
  }
  void skip(const Header& h, std::uint64_t length) {
    if (!file_.seek(file_.position() + length)) truncated(h);
  }

  bool is_sequence(const Header& h, const Encoding& e) const {
    return e.explicit_vr && h.vr[0] == 'S' && h.vr[1] == 'Q';
  }
  bool is_unknown(const Header& h, const Encoding& e) const {
    return e.explicit_vr && h.vr[0] == 'U' && h.vr[1] == 'N';
  }

  // Delimiters have length 0 (PS3.5 7.5); GDCM would allocate any other length as a value.
  void nothing_follows(const Header& h) {
    if (h.length != 0) fail(h, "is a delimiter of length " + std::to_string(h.length) + ", not 0");
  }

  void check_expected(const Header& h, const Encoding& e) {
    const ExpectedElement* expected = expected_element(h.tag);
    if (!expected) return;
    if (e.explicit_vr && (h.vr[0] != expected->vr[0] || h.vr[1] != expected->vr[1]))
      fail(h, std::string("has VR ") + h.vr[0] + h.vr[1] + ", expected " + expected->vr);
    if (expected->length != 0 && h.length != expected->length)
      fail(h, "is " + std::to_string(h.length) + " bytes long, expected " +
                  std::to_string(expected->length));
  }

  // The retired RecognitionCode of ACR-NEMA files: GDCM asserts that it names ACR-NEMA.
  void check_recognition_code(const Header& h) {
    std::string value(std::min<std::uint32_t>(h.length, 64), '\0');
    const std::uint64_t start = file_.position();
    if (!file_.read(value.data(), value.size())) truncated(h);
    file_.seek(start);
    for (const char* known : {"ACR-NEMA", "ACRNEMA", "MIPS 2.0"})
      if (value.compare(0, std::strlen(known), known) == 0) return;
    fail(h, "(RecognitionCode) does not name ACR-NEMA");
  }

  // True when the next four bytes are an item tag: an implicit-VR value of defined length that
  // starts like this is a sequence, and GDCM parses it as one.
  bool item_follows(const Encoding& e) {
    unsigned char bytes[4];
    const std::uint64_t start = file_.position();
    if (!file_.read(bytes, 4)) return false;
    file_.seek(start);
    return (std::uint32_t{u16(bytes, e)} << 16 | u16(bytes + 2, e)) == kItem;
  }

  bool wanted(std::uint32_t tag) const {
    return std::binary_search(wanted_, wanted_ + wanted_count_, tag);
  }

  // Elements up to `end` (a defined-length item), or to an item delimiter (`undefined_item`), or
  // to the end of the file (the top level).
  void elements(const Encoding& e, std::uint64_t end, int depth, bool undefined_item) {
    const bool top_level = depth == 0;
    // A data set holds each tag once. A file of zeros is element (0000,0000) of length 0 over
    // and over: walked to its end, a terabyte of it took most of an hour.
    std::uint32_t previous_tag = 0;
    bool first = true;
    for (;;) {
      if (end != kNoEnd && file_.position() == end) return;
      if (top_level && file_.left() == 0) return;
      if (undefined_item && file_.left() == 0)
        throw Malformed{"an item has no delimiter before the end of the file", true};
      const Header h = header(e);
      if (h.tag == kItemDelimiter) {
        if (!undefined_item) fail(h, "is an item delimiter outside an item");
        nothing_follows(h);
        return;
      }
      if ((h.tag >> 16) == 0xFFFE) fail(h, "is an item tag among data elements");
      if (!first && h.tag == previous_tag) fail(h, "repeats the element before it");
      previous_tag = h.tag;
      first = false;
      if (top_level) scan_.last_tag = h.tag;
      if (h.tag == kPixelData) {
        // Nested pixel data (an icon in an Icon Image Sequence) is walked alike, not recorded.
        pixel_data(h, e, top_level ? &scan_ : nullptr);
      } else if (h.length == kUndefinedLength) {
        if (e.explicit_vr && !is_sequence(h, e) && !is_unknown(h, e))
          fail(h, "has an undefined length but is not a sequence");
        // An undefined-length UN is a sequence encoded as implicit VR little endian (CP-246).
        sequence(is_unknown(h, e) ? Encoding{false, false} : e, kNoEnd, depth + 1);
      } else {
        need(h, h.length, end);
        if (top_level) check_expected(h, e);
        if (top_level && h.tag == kRecognitionCode) check_recognition_code(h);
        if (is_sequence(h, e) || (!e.explicit_vr && h.length >= 8 && item_follows(e))) {
          sequence(e, file_.position() + h.length, depth + 1);
        } else if (top_level && wanted(h.tag) && h.length <= kMaxKeptValueBytes) {
          std::string value(h.length, '\0');
          if (!file_.read(value.data(), value.size())) truncated(h);
          scan_.values[h.tag] = std::move(value);
        } else {
          skip(h, h.length);
        }
      }
      if (end != kNoEnd && file_.position() > end)
        throw Malformed{"an element runs past the end of its item, at byte " +
                        std::to_string(file_.position())};
    }
  }

  // Items up to `end`, or to a sequence delimiter when `end` is kNoEnd.
  void sequence(const Encoding& e, std::uint64_t end, int depth) {
    if (depth > kMaxDepth) throw Malformed{"sequences nested more than 32 deep"};
    for (;;) {
      if (end != kNoEnd && file_.position() == end) return;
      if (end == kNoEnd && file_.left() == 0)
        throw Malformed{"a sequence has no delimiter before the end of the file", true};
      const Header h = header(e);
      if (h.tag == kSequenceDelimiter) {
        if (end != kNoEnd) fail(h, "is a sequence delimiter in a sequence of defined length");
        nothing_follows(h);
        return;
      }
      if (h.tag != kItem) fail(h, "is not an item, inside a sequence");
      if (h.length == kUndefinedLength) {
        elements(e, kNoEnd, depth + 1, true);
      } else {
        need(h, h.length, end);
        elements(e, file_.position() + h.length, depth + 1, false);
      }
    }
  }

  // Native pixel data is one value; encapsulated (compressed) pixel data is a sequence of
  // fragments ending in a sequence delimiter (PS3.5 A.4).
  // `record`: where the image's pixel data are described (nullptr for nested ones).
  void pixel_data(const Header& h, const Encoding& e, DicomFileScan* record) {
    if (e.explicit_vr && (h.vr[0] != 'O' || (h.vr[1] != 'B' && h.vr[1] != 'W')))
      fail(h, std::string("(pixel data) has VR ") + h.vr[0] + h.vr[1] + ", expected OB or OW");
    DicomFileScan ignored;
    DicomFileScan& scan = record ? *record : ignored;
    scan.has_pixel_data = true;
    if (h.length != kUndefinedLength) {
      need(h, h.length);
      scan.pixel_data_bytes = h.length;
      skip(h, h.length);
      return;
    }
    scan.pixel_data_encapsulated = true;
    bool offset_table_seen = false;  // the first item is the basic offset table (PS3.5 A.4)
    for (;;) {
      if (file_.left() == 0)
        throw Malformed{"the compressed pixel data has no end before the end of the file", true};
      const Header fragment = header(e);
      if (fragment.tag == kSequenceDelimiter) {
        nothing_follows(fragment);
        return;
      }
      if (fragment.tag != kItem) fail(fragment, "is not a fragment, inside the pixel data");
      if (fragment.length == kUndefinedLength) fail(fragment, "is a fragment of undefined length");
      need(fragment, fragment.length);
      scan.pixel_data_bytes += fragment.length;
      if (!record || !offset_table_seen) {
        offset_table_seen = true;
        skip(fragment, fragment.length);
        continue;
      }
      // Keep both ends of the fragment: the codestream's header and its end marker.
      const std::uint64_t start = file_.position();
      DicomFragment kept;
      kept.length = fragment.length;
      kept.head.resize(std::min<std::uint64_t>(fragment.length, kDicomFragmentHeadBytes));
      if (!file_.read(kept.head.data(), kept.head.size())) truncated(fragment);
      const std::size_t tail = static_cast<std::size_t>(
          std::min<std::uint64_t>(fragment.length, kDicomFragmentTailBytes));
      file_.seek(start + fragment.length - tail);
      kept.tail.resize(tail);
      if (!file_.read(kept.tail.data(), tail)) truncated(fragment);
      scan.fragments.push_back(std::move(kept));
    }
  }

  FileBytes& file_;
  const std::uint32_t* wanted_;
  std::size_t wanted_count_;
  DicomFileScan& scan_;
};

// PS3.5 9.1: digits and dots, at most 64 characters.
bool is_uid(const std::string& text) {
  return text.size() <= 64 && std::all_of(text.begin(), text.end(), [](char c) {
           return c == '.' || (c >= '0' && c <= '9');
         });
}

}  // namespace

std::string dicom_tag_text(std::uint32_t tag) {
  char text[16];
  std::snprintf(text, sizeof text, "(%04X,%04X)", static_cast<unsigned>(tag >> 16),
                static_cast<unsigned>(tag & 0xFFFF));
  return text;
}

bool has_dicom_preamble(const std::string& path) {
  // Not waiting for a FIFO's writer: only a regular file is looked at (FileBytes).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return false;
  struct stat status {};
  char bytes[132];
  const bool found = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode) &&
                     ::pread(fd, bytes, sizeof bytes, 0) == static_cast<ssize_t>(sizeof bytes) &&
                     std::memcmp(bytes + 128, "DICM", 4) == 0;
  ::close(fd);
  return found;
}

bool has_dicom_extension(const std::string& path) {
  const std::string extension = lowercase_extension(path);
  return extension == ".dcm" || extension == ".dicom";
}

std::optional<DicomFileScan> scan_dicom_file(const std::string& path, const std::uint32_t* wanted,
                                             std::size_t wanted_count, bool claimed) {
  FileBytes file(path);
  DicomFileScan scan;
  Walker walker(file, wanted, wanted_count, scan);
  char preamble[132];
  const bool has_preamble =
      file.read(preamble, sizeof preamble) && std::memcmp(preamble + 128, "DICM", 4) == 0;
  if (!has_preamble) file.seek(0);
  const bool dicom_for_sure = has_preamble || claimed;
  try {
    walker.meta_group();
    Encoding encoding;
    if (!scan.transfer_syntax_uid.empty() && !is_uid(scan.transfer_syntax_uid))
      throw Malformed{"its TransferSyntaxUID (0002,0010) is not a UID"};
    if (scan.transfer_syntax_uid.empty()) {
      // No meta group: an old file whose first element tells how it is encoded.
      const std::optional<Encoding> guessed = walker.guess_bare_encoding();
      if (!guessed) {
        if (!dicom_for_sure) return std::nullopt;
        if (file.size() == 0) throw Malformed{"the file is empty", true};
        throw Malformed{has_preamble ? "no DICOM data element follows the preamble"
                                     : "it does not start with a DICOM data element"};
      }
      encoding = *guessed;
      scan.transfer_syntax_uid =
          encoding.explicit_vr ? kExplicitLittleEndian : kImplicitLittleEndian;
    } else if (scan.transfer_syntax_uid == kImplicitLittleEndian) {
      encoding = Encoding{false, false};
    } else if (scan.transfer_syntax_uid == kExplicitBigEndian) {
      encoding = Encoding{true, true};
    } else if (scan.transfer_syntax_uid == kDeflatedLittleEndian) {
      throw Error(path, std::string("its data set is deflated (transfer syntax ") +
                            kDeflatedLittleEndian + "), which mvox does not read");
    } else {
      // Every other transfer syntax, compressed ones included, encodes the data set as explicit
      // VR little endian.
      encoding = Encoding{walker.next_element_has_vr(), false};
    }
    scan.big_endian = encoding.big_endian;
    walker.data_set(encoding);
  } catch (const Malformed& malformed) {
    if (!dicom_for_sure) return std::nullopt;
    throw Error(path, (malformed.truncated ? "truncated DICOM file: " : "malformed DICOM file: ") +
                          malformed.problem);
  }
  return scan;
}

}  // namespace mvox
