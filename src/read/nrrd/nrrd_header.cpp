#include "read/nrrd/nrrd_header.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "error.h"
#include "read/header_text.h"
#include "write/mesh/world_transform.h"

namespace mvox {
namespace {

// Field names from the NRRD format definition, with teem's alternative spellings mapped to one.
struct FieldName {
  const char* spelling;
  const char* canonical;
};
constexpr FieldName kFields[] = {
    {"type", "type"},
    {"dimension", "dimension"},
    {"sizes", "sizes"},
    {"encoding", "encoding"},
    {"endian", "endian"},
    {"spacings", "spacings"},
    {"space", "space"},
    {"space dimension", "space dimension"},
    {"space directions", "space directions"},
    {"space origin", "space origin"},
    {"kinds", "kinds"},
    {"data file", "data file"},
    {"datafile", "data file"},
    {"line skip", "line skip"},
    {"lineskip", "line skip"},
    {"byte skip", "byte skip"},
    {"byteskip", "byte skip"},
    // Read and ignored: they describe the data but do not change how it is sampled or placed.
    {"content", "content"},
    {"number", "number"},
    {"block size", "block size"},
    {"blocksize", "block size"},
    {"thicknesses", "thicknesses"},
    {"axis mins", "axis mins"},
    {"axismins", "axis mins"},
    {"axis maxs", "axis maxs"},
    {"axismaxs", "axis maxs"},
    {"centers", "centers"},
    {"centerings", "centers"},
    {"labels", "labels"},
    {"units", "units"},
    {"min", "min"},
    {"max", "max"},
    {"old min", "old min"},
    {"oldmin", "old min"},
    {"old max", "old max"},
    {"oldmax", "old max"},
    {"sample units", "sample units"},
    {"sampleunits", "sample units"},
    {"space units", "space units"},
    {"measurement frame", "measurement frame"},
};

// Teem's type spellings. `sample` is set for the types mvox reads; `description` names the
// others in the refusal.
struct TypeName {
  const char* spelling;
  bool supported;
  StoredSample sample;
  const char* description;
};
constexpr TypeName kTypes[] = {
    {"uchar", true, StoredSample::u8, ""},
    {"unsigned char", true, StoredSample::u8, ""},
    {"uint8", true, StoredSample::u8, ""},
    {"uint8_t", true, StoredSample::u8, ""},
    {"signed char", true, StoredSample::i8, ""},
    {"int8", true, StoredSample::i8, ""},
    {"int8_t", true, StoredSample::i8, ""},
    {"short", true, StoredSample::i16, ""},
    {"short int", true, StoredSample::i16, ""},
    {"signed short", true, StoredSample::i16, ""},
    {"signed short int", true, StoredSample::i16, ""},
    {"int16", true, StoredSample::i16, ""},
    {"int16_t", true, StoredSample::i16, ""},
    {"ushort", true, StoredSample::u16, ""},
    {"unsigned short", true, StoredSample::u16, ""},
    {"unsigned short int", true, StoredSample::u16, ""},
    {"uint16", true, StoredSample::u16, ""},
    {"uint16_t", true, StoredSample::u16, ""},
    {"float", true, StoredSample::f32, ""},
    {"int", false, StoredSample::u8, "32-bit signed integer"},
    {"signed int", false, StoredSample::u8, "32-bit signed integer"},
    {"int32", false, StoredSample::u8, "32-bit signed integer"},
    {"int32_t", false, StoredSample::u8, "32-bit signed integer"},
    {"uint", false, StoredSample::u8, "32-bit unsigned integer"},
    {"unsigned int", false, StoredSample::u8, "32-bit unsigned integer"},
    {"uint32", false, StoredSample::u8, "32-bit unsigned integer"},
    {"uint32_t", false, StoredSample::u8, "32-bit unsigned integer"},
    {"longlong", false, StoredSample::u8, "64-bit signed integer"},
    {"long long", false, StoredSample::u8, "64-bit signed integer"},
    {"long long int", false, StoredSample::u8, "64-bit signed integer"},
    {"signed long long", false, StoredSample::u8, "64-bit signed integer"},
    {"signed long long int", false, StoredSample::u8, "64-bit signed integer"},
    {"int64", false, StoredSample::u8, "64-bit signed integer"},
    {"int64_t", false, StoredSample::u8, "64-bit signed integer"},
    {"ulonglong", false, StoredSample::u8, "64-bit unsigned integer"},
    {"unsigned long long", false, StoredSample::u8, "64-bit unsigned integer"},
    {"unsigned long long int", false, StoredSample::u8, "64-bit unsigned integer"},
    {"uint64", false, StoredSample::u8, "64-bit unsigned integer"},
    {"uint64_t", false, StoredSample::u8, "64-bit unsigned integer"},
    {"double", false, StoredSample::u8, "64-bit float"},
    {"block", false, StoredSample::u8, "opaque blocks"},
};

// Axis kinds that hold one scalar sample per voxel. The others (RGB-color, vector, list, ...)
// make an axis a sample's components, which the engine cannot classify.
constexpr const char* kScalarKinds[] = {"domain", "space", "time", "none", "???", "stub", "scalar"};

// Named spaces and their dimension; "-time" spaces add a fourth coordinate.
struct SpaceName {
  const char* name;
  int dimension;
};
constexpr SpaceName kSpaces[] = {
    {"right-anterior-superior", 3},
    {"ras", 3},
    {"left-anterior-superior", 3},
    {"las", 3},
    {"left-posterior-superior", 3},
    {"lps", 3},
    {"scanner-xyz", 3},
    {"3d-right-handed", 3},
    {"3d-left-handed", 3},
    {"right-anterior-superior-time", 4},
    {"rast", 4},
    {"left-anterior-superior-time", 4},
    {"last", 4},
    {"left-posterior-superior-time", 4},
    {"lpst", 4},
    {"scanner-xyz-time", 4},
    {"3d-right-handed-time", 4},
    {"3d-left-handed-time", 4},
};

struct FieldValue {
  std::string_view text;
  std::size_t line = 0;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& file_name) : text_(text), file_(file_name) {}
  NrrdHeader parse();

 private:
  [[noreturn]] void fail(std::size_t line, const std::string& problem) const {
    throw Error(file_, "line " + std::to_string(line) + ": " + problem);
  }
  [[noreturn]] void fail_field(const char* field, const std::string& problem) const {
    fail(fields_.at(field).line, std::string(field) + ": " + problem);
  }
  void read_fields();
  const FieldValue* find(const char* field) const {
    const auto it = fields_.find(field);
    return it == fields_.end() ? nullptr : &it->second;
  }
  const FieldValue& require(const char* field) const {
    const FieldValue* value = find(field);
    if (!value) throw Error(file_, std::string("the header has no \"") + field + ":\" field");
    return *value;
  }
  std::vector<std::string_view> per_axis_words(const char* field) const;
  void read_type();
  void read_sizes();
  void read_encoding_and_endian();
  int read_space_dimension() const;
  std::vector<double> read_vector(const char* field, std::string_view token, int count) const;
  void read_geometry();
  void read_kinds() const;
  void read_data_location();

  std::string_view text_;
  const std::string& file_;
  std::map<std::string, FieldValue> fields_;
  NrrdHeader header_;
  std::size_t dimension_ = 0;
};

void Parser::read_fields() {
  std::vector<std::size_t> offsets;
  const std::vector<HeaderLine> lines = split_header_lines(text_, &offsets);
  if (lines.empty() || lines[0].text.substr(0, 4) != "NRRD") {
    throw Error(file_, "not a NRRD file: the first line is not NRRD0001 .. NRRD0005");
  }
  const std::string_view magic = trim(lines[0].text);
  if (magic.size() != 8 || magic.substr(0, 7) != "NRRD000" || magic[7] < '1' || magic[7] > '5') {
    fail(1, "unknown NRRD version " + quoted(magic) + ", expected NRRD0001 .. NRRD0005");
  }
  header_.header_bytes = text_.size();
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const HeaderLine& line = lines[i];
    if (trim(line.text).empty()) {  // the blank line that ends the header
      header_.header_bytes = offsets[i];
      header_.ended_by_blank_line = true;
      return;
    }
    if (line.text.front() == '#') continue;
    const std::size_t colon = line.text.find(':');
    if (colon == std::string_view::npos)
      fail(line.number, "expected FIELD: VALUE, got " + quoted(line.text));
    if (colon + 1 < line.text.size() && line.text[colon + 1] == '=') continue;  // key:=value
    const std::string name = lowercase(trim(line.text.substr(0, colon)));
    const FieldName* known =
        std::find_if(std::begin(kFields), std::end(kFields),
                     [&](const FieldName& field) { return name == field.spelling; });
    if (known == std::end(kFields)) {
      fail(line.number, "unknown field " + quoted(line.text.substr(0, colon)));
    }
    const FieldValue value{trim(line.text.substr(colon + 1)), line.number};
    const auto [it, inserted] = fields_.emplace(known->canonical, value);
    if (!inserted) {
      fail(line.number, std::string(known->canonical) + ": given again (first on line " +
                            std::to_string(it->second.line) + ")");
    }
  }
}

std::vector<std::string_view> Parser::per_axis_words(const char* field) const {
  const std::vector<std::string_view> words = split_words(find(field)->text);
  if (words.size() != dimension_) {
    fail_field(field, "expected " + std::to_string(dimension_) + " values (dimension " +
                          std::to_string(dimension_) + "), got " + std::to_string(words.size()));
  }
  return words;
}

void Parser::read_type() {
  const FieldValue& field = require("type");
  // "unsigned  short" and "Unsigned Short" are the same type.
  std::string spelling;
  for (std::string_view word : split_words(field.text)) {
    if (!spelling.empty()) spelling += ' ';
    spelling += lowercase(word);
  }
  const TypeName* type = std::find_if(std::begin(kTypes), std::end(kTypes),
                                      [&](const TypeName& t) { return spelling == t.spelling; });
  if (type == std::end(kTypes)) fail_field("type", "unknown type " + quoted(field.text));
  if (!type->supported) {
    fail_field("type", quoted(field.text) + " (" + type->description +
                           ") is not supported: mvox reads uchar, signed char, short, ushort "
                           "and float samples; convert the volume to one of those");
  }
  header_.volume.stored = type->sample;
  header_.volume.info.type = engine_sample_type(type->sample);
}

void Parser::read_sizes() {
  const FieldValue& field = require("dimension");
  std::uint64_t dimension = 0;
  if (!parse_unsigned(field.text, 16, &dimension) || dimension == 0) {
    fail_field("dimension", "expected a whole number from 1 to 16, got " + quoted(field.text));
  }
  if (dimension != 3 && dimension != 2) {
    fail_field("dimension", std::to_string(dimension) +
                                " is not supported: mvox reads 3-D volumes (or 2-D, one slice)");
  }
  dimension_ = dimension;
  require("sizes");
  const std::vector<std::string_view> words = per_axis_words("sizes");
  std::uint64_t sizes[3] = {1, 1, 1};
  for (std::size_t axis = 0; axis < dimension_; ++axis) {
    if (!parse_unsigned(words[axis], std::numeric_limits<std::uint32_t>::max(), &sizes[axis]) ||
        sizes[axis] == 0) {
      fail_field("sizes", "size " + quoted(words[axis]) + " of axis " + std::to_string(axis) +
                              " is not a whole number from 1 to 4294967295");
    }
  }
  if (!volume_size_fits(sizes[0], sizes[1], sizes[2], stored_sample_bytes(header_.volume.stored))) {
    fail_field("sizes", quoted(find("sizes")->text) +
                            " make a volume too large to address (over 2^63 bytes)");
  }
  header_.volume.info.width = static_cast<std::uint32_t>(sizes[0]);
  header_.volume.info.height = static_cast<std::uint32_t>(sizes[1]);
  header_.volume.info.depth = static_cast<std::uint32_t>(sizes[2]);
}

void Parser::read_encoding_and_endian() {
  const FieldValue& encoding = require("encoding");
  const std::string name = lowercase(encoding.text);
  if (name == "raw") {
    header_.volume.compression = Compression::none;
  } else if (name == "gzip" || name == "gz") {
    header_.volume.compression = Compression::gzip;
  } else if (name == "txt" || name == "text" || name == "ascii" || name == "hex" || name == "bz2" ||
             name == "bzip2" || name == "zrl") {
    fail_field("encoding", quoted(encoding.text) + " is not supported: mvox reads raw and gzip");
  } else {
    fail_field("encoding", "unknown encoding " + quoted(encoding.text));
  }

  const FieldValue* endian = find("endian");
  if (!endian) {
    if (stored_sample_bytes(header_.volume.stored) > 1) {
      throw Error(file_,
                  "the header has no \"endian:\" field, needed for samples wider than "
                  "a byte");
    }
    return;
  }
  const std::string order = lowercase(endian->text);
  if (order == "little") {
    header_.volume.byte_order = ByteOrder::little;
  } else if (order == "big") {
    header_.volume.byte_order = ByteOrder::big;
  } else {
    fail_field("endian", "expected little or big, got " + quoted(endian->text));
  }
}

int Parser::read_space_dimension() const {
  const FieldValue* space = find("space");
  const FieldValue* space_dimension = find("space dimension");
  if (space && space_dimension) {
    fail_field("space dimension", "given with \"space:\" (line " + std::to_string(space->line) +
                                      "); the format allows only one of them");
  }
  int dimension = 0;
  if (space) {
    const std::string name = lowercase(space->text);
    const SpaceName* known = std::find_if(std::begin(kSpaces), std::end(kSpaces),
                                          [&](const SpaceName& s) { return name == s.name; });
    if (known == std::end(kSpaces)) fail_field("space", "unknown space " + quoted(space->text));
    dimension = known->dimension;
  } else if (space_dimension) {
    std::uint64_t value = 0;
    if (!parse_unsigned(space_dimension->text, 16, &value) || value == 0) {
      fail_field("space dimension",
                 "expected a whole number from 1 to 16, got " + quoted(space_dimension->text));
    }
    dimension = static_cast<int>(value);
  } else {
    return 0;
  }
  if (dimension < 2 || dimension > 3) {
    const char* field = space ? "space" : "space dimension";
    fail_field(field, "a " + std::to_string(dimension) +
                          "-dimensional space is not supported: mvox places volumes in 2-D or "
                          "3-D space");
  }
  return dimension;
}

// Parses "(x,y,z)" with `count` components into a 3-vector (missing components 0).
std::vector<double> Parser::read_vector(const char* field, std::string_view token,
                                        int count) const {
  if (token.size() < 2 || token.front() != '(' || token.back() != ')') {
    fail_field(field, "expected a vector like (1,0,0), got " + quoted(token));
  }
  std::vector<double> vector(3, 0.0);
  std::string_view inside = token.substr(1, token.size() - 2);
  int index = 0;
  for (;;) {
    const std::size_t comma = inside.find(',');
    const std::string_view part = trim(inside.substr(0, comma));
    if (index >= count || !parse_real(part, false, &vector[static_cast<std::size_t>(index)])) {
      fail_field(field, "expected a vector of " + std::to_string(count) +
                            " finite numbers (space dimension " + std::to_string(count) +
                            "), got " + quoted(token));
    }
    ++index;
    if (comma == std::string_view::npos) break;
    inside.remove_prefix(comma + 1);
  }
  if (index != count) {
    fail_field(field, "expected a vector of " + std::to_string(count) +
                          " numbers (space dimension " + std::to_string(count) + "), got " +
                          quoted(token));
  }
  return vector;
}

// Splits "(1, 0,0) none (0,0,1)" into "(1, 0,0)", "none", "(0,0,1)": vectors may hold blanks.
std::vector<std::string_view> split_vectors(std::string_view text) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i >= text.size()) break;
    const std::size_t start = i;
    if (text[i] == '(') {
      const std::size_t close = text.find(')', i);
      i = close == std::string_view::npos ? text.size() : close + 1;
    } else {
      while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    }
    tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

void Parser::read_geometry() {
  VolumeInfo& info = header_.volume.info;
  const int space_dimension = read_space_dimension();
  const FieldValue* directions = find("space directions");
  const FieldValue* spacings = find("spacings");
  const FieldValue* origin = find("space origin");

  if (directions && spacings) {
    fail_field("spacings", "given with \"space directions:\" (line " +
                               std::to_string(directions->line) +
                               "), which already set the spacing; the format allows only one");
  }
  if ((directions || origin) && space_dimension == 0) {
    const char* field = directions ? "space directions" : "space origin";
    fail_field(field, "needs a \"space:\" or \"space dimension:\" field before it means anything");
  }

  if (directions) {
    const std::vector<std::string_view> tokens = split_vectors(directions->text);
    if (tokens.size() != dimension_) {
      fail_field("space directions", "expected " + std::to_string(dimension_) +
                                         " vectors (dimension " + std::to_string(dimension_) +
                                         "), got " + std::to_string(tokens.size()));
    }
    for (std::size_t axis = 0; axis < dimension_; ++axis) {
      if (lowercase(tokens[axis]) == "none") {
        fail_field("space directions", "axis " + std::to_string(axis) +
                                           " is \"none\" (not a spatial axis); mvox needs a "
                                           "direction for every axis");
      }
      const std::vector<double> vector =
          read_vector("space directions", tokens[axis], space_dimension);
      if (!set_axis_from_vector(info, static_cast<int>(axis), vector.data())) {
        fail_field("space directions", "the direction of axis " + std::to_string(axis) + " " +
                                           quoted(tokens[axis]) +
                                           " has zero length or is too long");
      }
    }
    if (dimension_ == 2 && !complete_third_axis(info)) {
      fail_field("space directions", "the two axes are parallel");
    }
    if (dimension_ == 3 && !WorldTransform::of_volume(info).axes_span_space()) {
      fail_field("space directions",
                 "the three axes are parallel or coplanar, so they cannot place a volume");
    }
  } else if (spacings) {
    const std::vector<std::string_view> words = per_axis_words("spacings");
    for (std::size_t axis = 0; axis < dimension_; ++axis) {
      double spacing = 0;
      if (!parse_real(words[axis], true, &spacing) || spacing == 0) {
        fail_field("spacings", "spacing " + quoted(words[axis]) + " of axis " +
                                   std::to_string(axis) + " is not a non-zero finite number");
      }
      if (std::isnan(spacing)) continue;  // NaN: "no spacing known"; keep 1
      // A negative spacing runs the axis backwards: keep the spacing a size, turn the axis.
      double vector[3] = {0, 0, 0};
      vector[axis] = spacing;
      if (!set_axis_from_vector(info, static_cast<int>(axis), vector)) {
        fail_field("spacings", "spacing " + quoted(words[axis]) + " of axis " +
                                   std::to_string(axis) + " is not a non-zero finite number");
      }
    }
  }

  if (origin) {
    const std::vector<std::string_view> tokens = split_vectors(origin->text);
    if (tokens.size() != 1) {
      fail_field("space origin", "expected one vector like (0,0,0), got " + quoted(origin->text));
    }
    const std::vector<double> vector = read_vector("space origin", tokens[0], space_dimension);
    for (int i = 0; i < 3; ++i) info.origin[i] = vector[static_cast<std::size_t>(i)];
  }
}

void Parser::read_kinds() const {
  if (!find("kinds")) return;
  const std::vector<std::string_view> words = per_axis_words("kinds");
  for (std::size_t axis = 0; axis < dimension_; ++axis) {
    const std::string kind = lowercase(words[axis]);
    if (std::none_of(std::begin(kScalarKinds), std::end(kScalarKinds),
                     [&](const char* scalar) { return kind == scalar; })) {
      fail_field("kinds", "axis " + std::to_string(axis) + " is of kind " + quoted(words[axis]) +
                              ": its samples are components of one value (colour, vector, ...); "
                              "mvox reads one scalar per voxel");
    }
  }
}

void Parser::read_data_location() {
  if (const FieldValue* data_file = find("data file")) {
    const std::vector<std::string_view> words = split_words(data_file->text);
    if (words.empty()) fail_field("data file", "no file name given");
    if (words[0] == "LIST" ||
        (words.size() >= 4 && data_file->text.find('%') != std::string_view::npos)) {
      fail_field("data file",
                 "lists and numbered patterns of data files are not supported: "
                 "give one data file");
    }
    header_.data_file = std::string(data_file->text);
  } else if (!header_.ended_by_blank_line) {
    throw Error(file_,
                "the header names no \"data file:\" and no blank line ends it, so it has no data");
  }

  if (const FieldValue* line_skip = find("line skip")) {
    if (!parse_unsigned(line_skip->text, std::numeric_limits<std::int64_t>::max(),
                        &header_.line_skip)) {
      fail_field("line skip", "expected a whole number, got " + quoted(line_skip->text));
    }
  }
  if (const FieldValue* byte_skip = find("byte skip")) {
    if (!parse_signed(byte_skip->text, std::numeric_limits<std::int64_t>::max(),
                      &header_.byte_skip) ||
        header_.byte_skip < -1) {
      fail_field("byte skip", "expected a whole number or -1, got " + quoted(byte_skip->text));
    }
    if (header_.byte_skip == -1 && header_.volume.compression != Compression::none) {
      fail_field("byte skip", "-1 (data at the end of the file) needs raw encoding");
    }
  }
}

NrrdHeader Parser::parse() {
  read_fields();
  read_type();
  read_sizes();
  read_encoding_and_endian();
  read_geometry();
  read_kinds();
  read_data_location();
  return header_;
}

}  // namespace

NrrdHeader parse_nrrd_header(std::string_view text, const std::string& file_name) {
  return Parser(text, file_name).parse();
}

}  // namespace mvox
