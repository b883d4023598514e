#include "read/ply/ply_reader.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>

#include "error.h"
#include "read/file_bytes.h"

namespace mvox {
namespace {

// HEADER MODEL ------------------------------------------------------------------------------

enum class ScalarType : std::uint8_t {
  int8,
  uint8,
  int16,
  uint16,
  int32,
  uint32,
  float32,
  float64
};

struct TypeName {
  std::string_view name;
  ScalarType type;
};

// The PLY 1.0 names and the sized aliases that later writers (VTK, Open3D) use.
constexpr TypeName kTypeNames[] = {
    {"char", ScalarType::int8},      {"int8", ScalarType::int8},
    {"uchar", ScalarType::uint8},    {"uint8", ScalarType::uint8},
    {"short", ScalarType::int16},    {"int16", ScalarType::int16},
    {"ushort", ScalarType::uint16},  {"uint16", ScalarType::uint16},
    {"int", ScalarType::int32},      {"int32", ScalarType::int32},
    {"uint", ScalarType::uint32},    {"uint32", ScalarType::uint32},
    {"float", ScalarType::float32},  {"float32", ScalarType::float32},
    {"double", ScalarType::float64}, {"float64", ScalarType::float64},
};

std::size_t scalar_bytes(ScalarType type) {
  switch (type) {
    case ScalarType::int8:
    case ScalarType::uint8: return 1;
    case ScalarType::int16:
    case ScalarType::uint16: return 2;
    case ScalarType::int32:
    case ScalarType::uint32:
    case ScalarType::float32: return 4;
    case ScalarType::float64: return 8;
  }
  return 8;
}

bool is_integer(ScalarType type) {
  return type != ScalarType::float32 && type != ScalarType::float64;
}

// What the reader does with a property's values.
enum class Role : std::uint8_t { skip, x, y, z, nx, ny, nz, vertex_indices };

struct Property {
  std::string name;
  bool is_list = false;
  ScalarType count_type = ScalarType::uint8;  // lists only
  ScalarType type = ScalarType::float32;      // the scalar, or the list's items
  Role role = Role::skip;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  bool is_vertex = false;
  bool is_face = false;
};

enum class Format : std::uint8_t { ascii, binary_little_endian, binary_big_endian };

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::uint64_t vertex_count = 0;
  bool vertex_normals = false;  // nx, ny, nz are read
  std::size_t body_offset = 0;
};

// Header text goes into messages; keep it short and printable whatever the file holds.
std::string printable(std::string_view text) {
  constexpr std::size_t kShownChars = 40;
  std::string result;
  for (std::size_t i = 0; i < text.size() && i < kShownChars; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    result += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (text.size() > kShownChars) result += "...";
  return result;
}

std::string quoted(std::string_view text) { return "\"" + printable(text) + "\""; }

// The largest value a list's count can have.
std::uint64_t most_list_count(ScalarType count_type) {
  switch (count_type) {
    case ScalarType::int8: return 127;
    case ScalarType::uint8: return 255;
    case ScalarType::int16: return 32767;
    case ScalarType::uint16: return 65535;
    case ScalarType::int32: return 2147483647;
    case ScalarType::uint32: return 4294967295;
    case ScalarType::float32:
    case ScalarType::float64: break;
  }
  return std::numeric_limits<std::uint64_t>::max();
}

// The most bytes a file with this header can hold: for a binary body, every element's count
// times its largest record (lists at their count type's largest count), saturating; for ASCII,
// whose numbers may be spaced at will, no limit.
std::uint64_t most_file_bytes(const Header& header) {
  constexpr std::uint64_t kNoLimit = std::numeric_limits<std::uint64_t>::max();
  if (header.format == Format::ascii) return kNoLimit;
  const auto saturating_add = [](std::uint64_t a, std::uint64_t b) {
    return a > kNoLimit - b ? kNoLimit : a + b;
  };
  const auto saturating_multiply = [](std::uint64_t a, std::uint64_t b) {
    return b != 0 && a > kNoLimit / b ? kNoLimit : a * b;
  };
  std::uint64_t most = header.body_offset;
  for (const Element& element : header.elements) {
    std::uint64_t record = 0;
    for (const Property& property : element.properties) {
      std::uint64_t bytes = scalar_bytes(property.type);
      if (property.is_list)
        bytes = saturating_add(scalar_bytes(property.count_type),
                               saturating_multiply(most_list_count(property.count_type), bytes));
      record = saturating_add(record, bytes);
    }
    most = saturating_add(most, saturating_multiply(element.count, record));
  }
  return most;
}

// PASS 1: HEADER ------------------------------------------------------------------------------

constexpr const char* kNoEndHeader = "header has no end_header line";

class HeaderParser {
 public:
  HeaderParser(const char* data, std::size_t size, const std::string& name)
      : data_(data), size_(size), name_(name) {}

  Header parse() {
    std::string_view line;
    if (!next_line(&line) || line != "ply") {
      throw Error(name_, "not a PLY file: the first line is not \"ply\"");
    }
    bool have_format = false;
    for (;;) {
      if (!next_line(&line)) throw Error(name_, kNoEndHeader);
      split(line);
      if (tokens_.empty()) fail("empty header line");
      const std::string_view keyword = tokens_[0];
      if (keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "end_header") {
        expect_tokens(1);
        if (!have_format) fail("end_header before the format line");
        break;
      }
      if (keyword == "format") {
        if (have_format) fail("second format line");
        expect_tokens(3);
        if (tokens_[1] == "ascii") {
          header_.format = Format::ascii;
        } else if (tokens_[1] == "binary_little_endian") {
          header_.format = Format::binary_little_endian;
        } else if (tokens_[1] == "binary_big_endian") {
          header_.format = Format::binary_big_endian;
        } else {
          fail("unknown format " + quoted(tokens_[1]));
        }
        if (tokens_[2] != "1.0") fail("unsupported PLY version " + quoted(tokens_[2]));
        have_format = true;
      } else if (keyword == "element") {
        if (!have_format) fail("element before the format line");
        parse_element();
      } else if (keyword == "property") {
        if (header_.elements.empty()) fail("property before any element");
        parse_property();
      } else {
        fail("unknown header keyword " + quoted(keyword));
      }
    }
    header_.body_offset = position_;
    assign_roles();
    return header_;
  }

 private:
  // The next '\n'-terminated line, without "\r\n" or "\n". False at the end of the data.
  bool next_line(std::string_view* line) {
    if (position_ >= size_) return false;
    const void* newline = std::memchr(data_ + position_, '\n', size_ - position_);
    if (newline == nullptr) return false;
    const std::size_t end = static_cast<std::size_t>(static_cast<const char*>(newline) - data_);
    std::size_t line_end = end;
    if (line_end > position_ && data_[line_end - 1] == '\r') --line_end;
    *line = std::string_view(data_ + position_, line_end - position_);
    position_ = end + 1;
    ++line_number_;
    return true;
  }

  void split(std::string_view line) {
    tokens_.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > start) tokens_.push_back(line.substr(start, i - start));
    }
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw Error(name_, "header line " + std::to_string(line_number_) + ": " + problem);
  }

  void expect_tokens(std::size_t count) const {
    if (tokens_.size() != count) {
      fail(quoted(tokens_[0]) + " line needs " + std::to_string(count - 1) + " values, has " +
           std::to_string(tokens_.size() - 1));
    }
  }

  ScalarType scalar_type(std::string_view name) const {
    for (const TypeName& entry : kTypeNames) {
      if (entry.name == name) return entry.type;
    }
    fail("unknown property type " + quoted(name));
  }

  void parse_element() {
    expect_tokens(3);
    Element element;
    element.name = std::string(tokens_[1]);
    const std::string_view count = tokens_[2];
    const auto [end, error] =
        std::from_chars(count.data(), count.data() + count.size(), element.count);
    if (error != std::errc() || end != count.data() + count.size()) {
      fail("element count " + quoted(count) + " is not a non-negative 64-bit integer");
    }
    for (const Element& other : header_.elements) {
      if (other.name == element.name) fail("second element " + quoted(element.name));
    }
    header_.elements.push_back(std::move(element));
  }

  void parse_property() {
    Property property;
    if (tokens_.size() >= 2 && tokens_[1] == "list") {
      expect_tokens(5);
      property.is_list = true;
      property.count_type = scalar_type(tokens_[2]);
      property.type = scalar_type(tokens_[3]);
      if (!is_integer(property.count_type)) fail("list length type must be an integer type");
      property.name = std::string(tokens_[4]);
    } else {
      expect_tokens(3);
      property.type = scalar_type(tokens_[1]);
      property.name = std::string(tokens_[2]);
    }
    Element& element = header_.elements.back();
    for (const Property& other : element.properties) {
      if (other.name == property.name) fail("second property " + quoted(property.name));
    }
    element.properties.push_back(std::move(property));
  }

  // Marks the properties the mesh needs, and checks that they are there and usable.
  void assign_roles() {
    bool have_vertex = false;
    for (Element& element : header_.elements) {
      if (element.count > 0 && element.properties.empty()) {
        throw Error(name_, "element " + quoted(element.name) + " has no properties");
      }
      if (element.name == "vertex") {
        have_vertex = true;
        element.is_vertex = true;
        header_.vertex_count = element.count;
        // Face indices are stored as 32-bit values.
        if (element.count > std::numeric_limits<std::uint32_t>::max()) {
          throw Error(name_, "more than 2^32 - 1 vertices");
        }
        static constexpr std::string_view kAxisNames[3] = {"x", "y", "z"};
        static constexpr Role kAxisRoles[3] = {Role::x, Role::y, Role::z};
        for (int axis = 0; axis < 3; ++axis) {
          Property* found = nullptr;
          for (Property& property : element.properties) {
            if (property.name == kAxisNames[axis]) found = &property;
          }
          if (found == nullptr) {
            throw Error(name_, "vertex element has no property " + quoted(kAxisNames[axis]));
          }
          if (found->is_list) {
            throw Error(name_, "vertex property " + quoted(kAxisNames[axis]) + " is a list");
          }
          found->role = kAxisRoles[axis];
        }
        // Normals are read only when all three are scalar properties; otherwise skipped.
        static constexpr std::string_view kNormalNames[3] = {"nx", "ny", "nz"};
        static constexpr Role kNormalRoles[3] = {Role::nx, Role::ny, Role::nz};
        Property* normal[3] = {};
        for (int axis = 0; axis < 3; ++axis)
          for (Property& property : element.properties)
            if (property.name == kNormalNames[axis] && !property.is_list) normal[axis] = &property;
        if (normal[0] && normal[1] && normal[2]) {
          header_.vertex_normals = true;
          for (int axis = 0; axis < 3; ++axis) normal[axis]->role = kNormalRoles[axis];
        }
      } else if (element.name == "face") {
        element.is_face = true;
        Property* found = nullptr;
        for (Property& property : element.properties) {
          if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
          if (found != nullptr) {
            throw Error(name_, "face element has both vertex_indices and vertex_index");
          }
          found = &property;
        }
        if (found == nullptr) throw Error(name_, "face element has no vertex_indices list");
        if (!found->is_list)
          throw Error(name_, "face property " + quoted(found->name) + " is not a list");
        if (!is_integer(found->type)) {
          throw Error(name_, "face property " + quoted(found->name) + " has non-integer indices");
        }
        found->role = Role::vertex_indices;
      }
    }
    if (!have_vertex) throw Error(name_, "no vertex element");
  }

  const char* data_;
  std::size_t size_;
  const std::string& name_;
  std::size_t position_ = 0;
  std::uint64_t line_number_ = 0;
  std::vector<std::string_view> tokens_;
  Header header_;
};

// PASS 2: BODY --------------------------------------------------------------------------------
// Two cursors with the same interface, so that parse_body() is written once and the format
// switch happens once per file, not once per value.

// Names the element instance being read, for messages ("face 12: vertex index 9 ...").
class Position {
 public:
  explicit Position(const std::string& name) : name_(name) {}
  void at(const Element& element, std::uint64_t index) {
    element_ = &element;
    index_ = index;
  }
  [[noreturn]] void fail(const std::string& problem, const std::string& suffix = {}) const {
    // Element names come from the file: printable, as every header word in a message.
    const std::string where = printable(element_->name) + " " + std::to_string(index_);
    throw Error(name_, where + suffix + ": " + problem);
  }
  // For problems of the file as a whole, not of one element.
  [[noreturn]] void fail_file(const std::string& problem) const { throw Error(name_, problem); }

 private:
  const std::string& name_;
  const Element* element_ = nullptr;
  std::uint64_t index_ = 0;
};

class BinaryCursor {
 public:
  BinaryCursor(const unsigned char* data, std::size_t size, bool big_endian, Position& position)
      : next_(data), end_(data + size), big_endian_(big_endian), position_(position) {}

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - next_); }
  static std::uint64_t min_instance_bytes(const Element& element) {
    std::uint64_t bytes = 0;
    for (const Property& property : element.properties) {
      bytes += scalar_bytes(property.is_list ? property.count_type : property.type);
    }
    return bytes;
  }

  std::int64_t read_integer(ScalarType type) {
    switch (type) {
      case ScalarType::int8: return sign_extend(load(1), 8);
      case ScalarType::uint8: return static_cast<std::int64_t>(load(1));
      case ScalarType::int16: return sign_extend(load(2), 16);
      case ScalarType::uint16: return static_cast<std::int64_t>(load(2));
      case ScalarType::int32: return sign_extend(load(4), 32);
      case ScalarType::uint32: return static_cast<std::int64_t>(load(4));
      case ScalarType::float32:
      case ScalarType::float64: break;  // refused by the header checks
    }
    position_.fail("internal error: integer read of a floating-point property");
  }

  double read_real(ScalarType type) {
    if (type == ScalarType::float32) {
      const auto bits = static_cast<std::uint32_t>(load(4));
      float value;
      std::memcpy(&value, &bits, sizeof value);
      return value;
    }
    if (type == ScalarType::float64) {
      const std::uint64_t bits = load(8);
      double value;
      std::memcpy(&value, &bits, sizeof value);
      return value;
    }
    return static_cast<double>(read_integer(type));
  }

  // Fails unless `count` items of `type` can still follow, before a loop runs over them.
  void require_items(ScalarType type, std::uint64_t count) const {
    if (count > remaining() / scalar_bytes(type)) position_.fail("file ends too early");
  }

  void skip_items(ScalarType type, std::uint64_t count) {
    require_items(type, count);
    next_ += count * scalar_bytes(type);
  }

  void end_instance() {}

  void finish() const {
    if (next_ != end_) {
      position_.fail_file(std::to_string(remaining()) + " bytes follow the last element");
    }
  }

 private:
  // Assembles the bytes in file order, so it does not matter how the host orders them.
  std::uint64_t load(std::size_t bytes) {
    if (remaining() < bytes) position_.fail("file ends too early");
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < bytes; ++i) {
      const std::size_t shift = big_endian_ ? 8 * (bytes - 1 - i) : 8 * i;
      value |= static_cast<std::uint64_t>(next_[i]) << shift;
    }
    next_ += bytes;
    return value;
  }

  // Two's complement by arithmetic, not by a narrowing cast.
  static std::int64_t sign_extend(std::uint64_t value, int bits) {
    const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
    return (value & sign) ? static_cast<std::int64_t>(value) - (std::int64_t{1} << bits)
                          : static_cast<std::int64_t>(value);
  }

  const unsigned char* next_;
  const unsigned char* end_;
  bool big_endian_;
  Position& position_;
};

class AsciiCursor {
 public:
  AsciiCursor(const char* data, std::size_t size, std::uint64_t first_line, Position& position)
      : next_(data), end_(data + size), line_(first_line), position_(position) {}

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - next_); }
  // Every value is a token of at least one character.
  static std::uint64_t min_instance_bytes(const Element& element) {
    return element.properties.size();
  }

  std::int64_t read_integer(ScalarType type) {
    const std::string_view text = token();
    std::int64_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) {
      fail(quoted(text) + " is not an integer");
    }
    std::int64_t low = 0;
    std::int64_t high = 0;
    switch (type) {
      case ScalarType::int8: low = INT8_MIN, high = INT8_MAX; break;
      case ScalarType::uint8: high = UINT8_MAX; break;
      case ScalarType::int16: low = INT16_MIN, high = INT16_MAX; break;
      case ScalarType::uint16: high = UINT16_MAX; break;
      case ScalarType::int32: low = INT32_MIN, high = INT32_MAX; break;
      case ScalarType::uint32: high = UINT32_MAX; break;
      case ScalarType::float32:
      case ScalarType::float64: fail("internal error: integer read of a floating-point property");
    }
    if (value < low || value > high) fail(quoted(text) + " is out of range for its type");
    return value;
  }

  double read_real(ScalarType type) {
    if (is_integer(type)) return static_cast<double>(read_integer(type));
    const std::string_view text = token();
    double value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) {
      fail(quoted(text) + " is not a number");
    }
    return value;
  }

  void require_items(ScalarType, std::uint64_t count) const {
    if (count > remaining()) fail("list is longer than the rest of the file");
  }

  void skip_items(ScalarType type, std::uint64_t count) {
    require_items(type, count);
    for (std::uint64_t i = 0; i < count; ++i) read_real(type);
  }

  // One element per line: nothing but blanks may follow its last value.
  void end_instance() {
    skip_blanks();
    if (next_ == end_) return;
    if (*next_ != '\n') fail("more values on the line than the header declares");
    ++next_;
    ++line_;
  }

  void finish() {
    for (; next_ != end_; ++next_) {
      if (*next_ == '\n') {
        ++line_;
      } else if (*next_ != ' ' && *next_ != '\t' && *next_ != '\r') {
        position_.fail_file("line " + std::to_string(line_) +
                            ": unexpected data after the last element");
      }
    }
  }

 private:
  void skip_blanks() {
    while (next_ != end_ && (*next_ == ' ' || *next_ == '\t' || *next_ == '\r')) ++next_;
  }

  std::string_view token() {
    skip_blanks();
    if (next_ == end_ || *next_ == '\n') fail("fewer values on the line than the header declares");
    const char* start = next_;
    while (next_ != end_ && *next_ != ' ' && *next_ != '\t' && *next_ != '\r' && *next_ != '\n') {
      ++next_;
    }
    return std::string_view(start, static_cast<std::size_t>(next_ - start));
  }

  [[noreturn]] void fail(const std::string& problem) const {
    position_.fail(problem, " (line " + std::to_string(line_) + ")");
  }

  const char* next_;
  const char* end_;
  std::uint64_t line_;
  Position& position_;
};

template <class Cursor>
void parse_body(Cursor& in, Position& position, const Header& header, PlyMesh& mesh) {
  for (const Element& element : header.elements) {
    // Checked before reserving anything: a header may claim 10^18 elements in a 100-byte file.
    const std::uint64_t min_bytes = Cursor::min_instance_bytes(element);
    if (element.count > 0 && (min_bytes == 0 || element.count > in.remaining() / min_bytes)) {
      position.fail_file("header declares " + std::to_string(element.count) + " " +
                         printable(element.name) +
                         " elements, more than the rest of the file can hold");
    }
    if (element.is_vertex) mesh.positions.reserve(element.count);
    if (element.is_vertex && header.vertex_normals) mesh.normals.reserve(element.count);
    if (element.is_face) mesh.face_offsets.reserve(element.count + 1);

    for (std::uint64_t index = 0; index < element.count; ++index) {
      position.at(element, index);
      std::array<float, 3> point = {0, 0, 0};
      std::array<float, 3> normal = {0, 0, 0};
      for (const Property& property : element.properties) {
        switch (property.role) {
          case Role::skip:
            if (property.is_list) {
              const std::int64_t count = in.read_integer(property.count_type);
              if (count < 0) position.fail("negative list length " + std::to_string(count));
              in.skip_items(property.type, static_cast<std::uint64_t>(count));
            } else {
              in.skip_items(property.type, 1);
            }
            break;
          case Role::x:
          case Role::y:
          case Role::z: {
            const double value = in.read_real(property.type);
            // Converting a double beyond float's range is undefined behaviour; NaN and infinity
            // have no place in a mesh either.
            if (!(std::fabs(value) <= std::numeric_limits<float>::max())) {
              position.fail("coordinate " + property.name + " is not a finite float");
            }
            point[static_cast<int>(property.role) - static_cast<int>(Role::x)] =
                static_cast<float>(value);
            break;
          }
          case Role::nx:
          case Role::ny:
          case Role::nz: {
            const double value = in.read_real(property.type);
            if (!(std::fabs(value) <= std::numeric_limits<float>::max())) {
              position.fail("normal " + property.name + " is not a finite float");
            }
            normal[static_cast<int>(property.role) - static_cast<int>(Role::nx)] =
                static_cast<float>(value);
            break;
          }
          case Role::vertex_indices: {
            const std::int64_t count = in.read_integer(property.count_type);
            if (count <= 0) position.fail("face with " + std::to_string(count) + " vertices");
            in.require_items(property.type, static_cast<std::uint64_t>(count));
            for (std::int64_t k = 0; k < count; ++k) {
              const std::int64_t vertex = in.read_integer(property.type);
              if (vertex < 0 || static_cast<std::uint64_t>(vertex) >= header.vertex_count) {
                position.fail("vertex index " + std::to_string(vertex) + " out of range (" +
                              std::to_string(header.vertex_count) + " vertices)");
              }
              mesh.face_indices.push_back(static_cast<std::uint32_t>(vertex));
            }
            break;
          }
        }
      }
      if (element.is_vertex) mesh.positions.push_back(point);
      if (element.is_vertex && header.vertex_normals) mesh.normals.push_back(normal);
      if (element.is_face) {
        if (mesh.face_indices.size() > std::numeric_limits<std::uint32_t>::max()) {
          position.fail("more than 2^32 - 1 face indices in all");
        }
        mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
      }
      in.end_instance();
    }
  }
  in.finish();
}

}  // namespace

PlyMesh parse_ply(const void* data, std::size_t size, const std::string& name_for_errors) {
  const char* text = static_cast<const char*>(data);
  if (size == 0) throw Error(name_for_errors, "empty file");
  HeaderParser header_parser(text, size, name_for_errors);
  const Header header = header_parser.parse();

  PlyMesh mesh;
  Position position(name_for_errors);
  const std::size_t body_size = size - header.body_offset;
  if (header.format == Format::ascii) {
    // Lines are counted from 1; the body starts after the header's lines.
    std::uint64_t first_line = 1;
    for (std::size_t i = 0; i < header.body_offset; ++i) first_line += text[i] == '\n';
    AsciiCursor in(text + header.body_offset, body_size, first_line, position);
    parse_body(in, position, header, mesh);
  } else {
    BinaryCursor in(static_cast<const unsigned char*>(data) + header.body_offset, body_size,
                    header.format == Format::binary_big_endian, position);
    parse_body(in, position, header, mesh);
  }
  return mesh;
}

PlyMesh read_ply(const std::string& path) {
  // The header is parsed from the file's first MiB before the rest is read, so that a file that
  // is not a PLY (/dev/zero, or 100 GiB of something else) is refused from its start rather than
  // read whole into memory. A header longer than that holds nothing a mesh needs.
  constexpr std::size_t kMostHeaderBytes = std::size_t{1} << 20;
  const StartCheck header_first{
      kMostHeaderBytes, [&path](const unsigned char* start, std::size_t size) {
        if (size == 0) throw Error(path, "empty file");
        try {
          return most_file_bytes(
              HeaderParser(reinterpret_cast<const char*>(start), size, path).parse());
        } catch (const Error& error) {
          // Cut by the window, not by the file's end: said so.
          if (size < kMostHeaderBytes || error.problem() != kNoEndHeader) throw;
          throw Error(path, std::string(kNoEndHeader) + " in its first MiB");
        }
      }};
  ReadBuffer bytes;
  read_file_bytes(path, bytes, std::numeric_limits<std::uint64_t>::max(), FileKinds::any,
                  header_first);
  return parse_ply(bytes.data(), bytes.size(), path);
}

}  // namespace mvox
