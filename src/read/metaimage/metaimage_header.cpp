#include "read/metaimage/metaimage_header.h"

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

// Keys mvox reads, lower case, with MetaIO's synonyms mapped to one name.
struct KeyName {
  const char* spelling;
  const char* canonical;
};
constexpr KeyName kKeys[] = {
    {"objecttype", "ObjectType"},
    {"ndims", "NDims"},
    {"dimsize", "DimSize"},
    {"elementtype", "ElementType"},
    {"elementspacing", "ElementSpacing"},
    {"elementsize", "ElementSize"},
    {"offset", "Offset"},
    {"origin", "Offset"},
    {"position", "Offset"},
    {"transformmatrix", "TransformMatrix"},
    {"rotation", "TransformMatrix"},
    {"orientation", "TransformMatrix"},
    {"elementbyteordermsb", "ElementByteOrderMSB"},
    {"binarydatabyteordermsb", "BinaryDataByteOrderMSB"},
    {"headersize", "HeaderSize"},
    {"compresseddata", "CompressedData"},
    {"compresseddatasize", "CompressedDataSize"},
    {"binarydata", "BinaryData"},
    {"elementnumberofchannels", "ElementNumberOfChannels"},
    {"elementdatafile", "ElementDataFile"},
};

struct ElementTypeName {
  const char* name;
  StoredSample sample;
};
constexpr ElementTypeName kElementTypes[] = {
    {"MET_UCHAR", StoredSample::u8},   {"MET_CHAR", StoredSample::i8},
    {"MET_USHORT", StoredSample::u16}, {"MET_SHORT", StoredSample::i16},
    {"MET_FLOAT", StoredSample::f32},
};

struct KeyValue {
  std::string_view key;  // as written, for messages
  std::string_view text;
  std::size_t line = 0;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& file_name) : text_(text), file_(file_name) {}
  MetaImageHeader parse();

 private:
  [[noreturn]] void fail(const char* key, const std::string& problem) const {
    const KeyValue& value = values_.at(key);
    throw Error(file_, "line " + std::to_string(value.line) + ": " + std::string(value.key) + ": " +
                           problem);
  }
  const KeyValue* find(const char* key) const {
    const auto it = values_.find(key);
    return it == values_.end() ? nullptr : &it->second;
  }
  const KeyValue& require(const char* key) const {
    const KeyValue* value = find(key);
    if (!value) throw Error(file_, std::string("the header has no ") + key + " line");
    return *value;
  }
  void read_lines();
  bool read_bool(const char* key, bool absent) const;
  std::vector<double> read_reals(const char* key, std::size_t count) const;
  void read_sizes();
  void read_element_type();
  void read_storage();
  void read_geometry();
  void read_data_file();

  std::string_view text_;
  const std::string& file_;
  std::map<std::string, KeyValue> values_;
  MetaImageHeader header_;
  std::size_t dimension_ = 0;
};

void Parser::read_lines() {
  std::vector<std::size_t> offsets;
  const std::vector<HeaderLine> lines = split_header_lines(text_, &offsets);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const HeaderLine& line = lines[i];
    if (trim(line.text).empty()) continue;
    const std::size_t equals = line.text.find('=');
    if (equals == std::string_view::npos) {
      throw Error(file_, "line " + std::to_string(line.number) + ": expected KEY = VALUE, got " +
                             quoted(line.text));
    }
    const std::string_view key = trim(line.text.substr(0, equals));
    const std::string lower = lowercase(key);
    const KeyName* known = std::find_if(std::begin(kKeys), std::end(kKeys),
                                        [&](const KeyName& k) { return lower == k.spelling; });
    if (known == std::end(kKeys)) continue;  // MetaIO keeps unknown keys as user fields
    const KeyValue value{key, trim(line.text.substr(equals + 1)), line.number};
    const auto [it, inserted] = values_.emplace(known->canonical, value);
    if (!inserted) {
      throw Error(file_, "line " + std::to_string(line.number) + ": " + std::string(key) +
                             ": given again (line " + std::to_string(it->second.line) + " gave " +
                             std::string(it->second.key) + ")");
    }
    // ElementDataFile is always the last key: whatever follows is data (LOCAL) or a list.
    if (std::string(known->canonical) == "ElementDataFile") {
      header_.header_bytes = offsets[i];
      return;
    }
  }
  throw Error(file_, "the header has no ElementDataFile line (it ends every MetaImage header)");
}

bool Parser::read_bool(const char* key, bool absent) const {
  const KeyValue* value = find(key);
  if (!value) return absent;
  const std::string text = lowercase(value->text);
  if (text == "true" || text == "t" || text == "1") return true;
  if (text == "false" || text == "f" || text == "0") return false;
  fail(key, "expected True or False, got " + quoted(value->text));
}

std::vector<double> Parser::read_reals(const char* key, std::size_t count) const {
  const std::vector<std::string_view> words = split_words(find(key)->text);
  std::vector<double> values(count, 0.0);
  bool ok = words.size() == count;
  for (std::size_t i = 0; ok && i < count; ++i) ok = parse_real(words[i], false, &values[i]);
  if (!ok) {
    fail(key,
         "expected " + std::to_string(count) + " finite numbers, got " + quoted(find(key)->text));
  }
  return values;
}

void Parser::read_sizes() {
  const KeyValue& ndims = require("NDims");
  std::uint64_t dimension = 0;
  if (!parse_unsigned(ndims.text, 16, &dimension) || (dimension != 2 && dimension != 3)) {
    fail("NDims", quoted(ndims.text) +
                      " is not supported: mvox reads 3-D volumes (or 2-D, one "
                      "slice)");
  }
  dimension_ = dimension;
  const KeyValue& dim_size = require("DimSize");
  const std::vector<std::string_view> words = split_words(dim_size.text);
  if (words.size() != dimension_) {
    fail("DimSize",
         "expected " + std::to_string(dimension_) + " sizes (NDims), got " + quoted(dim_size.text));
  }
  std::uint64_t sizes[3] = {1, 1, 1};
  for (std::size_t axis = 0; axis < dimension_; ++axis) {
    if (!parse_unsigned(words[axis], std::numeric_limits<std::uint32_t>::max(), &sizes[axis]) ||
        sizes[axis] == 0) {
      fail("DimSize", "size " + quoted(words[axis]) + " of axis " + std::to_string(axis) +
                          " is not a whole number from 1 to 4294967295");
    }
  }
  if (!volume_size_fits(sizes[0], sizes[1], sizes[2], stored_sample_bytes(header_.volume.stored))) {
    fail("DimSize",
         quoted(dim_size.text) + " make a volume too large to address (over 2^63 bytes)");
  }
  header_.volume.info.width = static_cast<std::uint32_t>(sizes[0]);
  header_.volume.info.height = static_cast<std::uint32_t>(sizes[1]);
  header_.volume.info.depth = static_cast<std::uint32_t>(sizes[2]);
}

void Parser::read_element_type() {
  const KeyValue& type = require("ElementType");
  const ElementTypeName* known =
      std::find_if(std::begin(kElementTypes), std::end(kElementTypes),
                   [&](const ElementTypeName& t) { return type.text == t.name; });
  if (known == std::end(kElementTypes)) {
    fail("ElementType", quoted(type.text) +
                            " is not supported: mvox reads MET_UCHAR, MET_CHAR, MET_USHORT, "
                            "MET_SHORT and MET_FLOAT; convert the volume to one of those");
  }
  header_.volume.stored = known->sample;
  header_.volume.info.type = engine_sample_type(known->sample);

  if (const KeyValue* channels = find("ElementNumberOfChannels")) {
    std::uint64_t count = 0;
    if (!parse_unsigned(channels->text, 1u << 20, &count) || count == 0) {
      fail("ElementNumberOfChannels", "expected a whole number, got " + quoted(channels->text));
    }
    if (count != 1) {
      fail("ElementNumberOfChannels", std::to_string(count) +
                                          " channels (colour or vector voxels): mvox reads one "
                                          "scalar per voxel");
    }
  }
}

void Parser::read_storage() {
  if (const KeyValue* object = find("ObjectType")) {
    if (lowercase(object->text) != "image") {
      fail("ObjectType", quoted(object->text) + " is not an image");
    }
  }
  if (!read_bool("BinaryData", true)) {
    fail("BinaryData", "False (samples written as text) is not supported: mvox reads binary data");
  }
  const bool element_msb = read_bool("ElementByteOrderMSB", false);
  const bool binary_msb = read_bool("BinaryDataByteOrderMSB", false);
  if (find("ElementByteOrderMSB") && find("BinaryDataByteOrderMSB") && element_msb != binary_msb) {
    fail("BinaryDataByteOrderMSB", "contradicts ElementByteOrderMSB (line " +
                                       std::to_string(find("ElementByteOrderMSB")->line) + ")");
  }
  header_.volume.byte_order = element_msb || binary_msb ? ByteOrder::big : ByteOrder::little;

  const bool compressed = read_bool("CompressedData", false);
  header_.volume.compression = compressed ? Compression::zlib : Compression::none;
  if (const KeyValue* size = find("CompressedDataSize")) {
    if (!parse_unsigned(size->text, std::numeric_limits<std::int64_t>::max(),
                        &header_.compressed_bytes)) {
      fail("CompressedDataSize", "expected a whole number, got " + quoted(size->text));
    }
  }
  if (const KeyValue* size = find("HeaderSize")) {
    if (!parse_signed(size->text, std::numeric_limits<std::int64_t>::max(), &header_.header_size) ||
        header_.header_size < -1) {
      fail("HeaderSize", "expected a whole number or -1, got " + quoted(size->text));
    }
    if (header_.header_size == -1 && compressed) {
      fail("HeaderSize", "-1 (data at the end of the file) needs uncompressed data");
    }
  }
}

void Parser::read_geometry() {
  VolumeInfo& info = header_.volume.info;
  // ElementSize is the extent of a voxel, not the distance between voxels; MetaIO uses it as
  // the spacing only when ElementSpacing is missing, and so does mvox.
  const char* spacing_key = find("ElementSpacing") ? "ElementSpacing"
                            : find("ElementSize")  ? "ElementSize"
                                                   : nullptr;
  std::vector<double> spacing(dimension_, 1.0);
  if (spacing_key) spacing = read_reals(spacing_key, dimension_);
  std::vector<double> matrix(dimension_ * dimension_, 0.0);
  for (std::size_t axis = 0; axis < dimension_; ++axis) matrix[axis * dimension_ + axis] = 1;
  if (find("TransformMatrix")) matrix = read_reals("TransformMatrix", dimension_ * dimension_);

  for (std::size_t axis = 0; axis < dimension_; ++axis) {
    if (spacing[axis] == 0) fail(spacing_key, "a spacing of 0 along axis " + std::to_string(axis));
    double direction[3] = {0, 0, 0};
    double length_squared = 0;
    for (std::size_t i = 0; i < dimension_; ++i) {
      direction[i] = matrix[axis * dimension_ + i];
      length_squared += direction[i] * direction[i];
    }
    if (!(length_squared > 0)) {
      fail("TransformMatrix", "the direction of axis " + std::to_string(axis) + " is zero");
    }
    // The unit direction times the spacing: a negative spacing turns the axis around and
    // leaves a positive voxel size, and a matrix row that is not quite unit length does not
    // change the spacing the header states.
    const double scale = spacing[axis] / std::sqrt(length_squared);
    for (double& component : direction) component *= scale;
    if (!set_axis_from_vector(info, static_cast<int>(axis), direction)) {
      fail(spacing_key ? spacing_key : "TransformMatrix",
           "axis " + std::to_string(axis) + " has no finite size");
    }
  }
  if (dimension_ == 2 && !complete_third_axis(info)) {
    fail("TransformMatrix", "the two axes are parallel");
  }
  if (dimension_ == 3 && !WorldTransform::of_volume(info).axes_span_space()) {
    fail("TransformMatrix",
         "is singular: its axes are parallel or coplanar, so they cannot place a volume");
  }
  if (find("Offset")) {
    const std::vector<double> offset = read_reals("Offset", dimension_);
    for (std::size_t i = 0; i < dimension_; ++i) info.origin[i] = offset[i];
  }
}

void Parser::read_data_file() {
  const KeyValue& data_file = require("ElementDataFile");
  const std::vector<std::string_view> words = split_words(data_file.text);
  if (words.empty()) fail("ElementDataFile", "no file name given");
  if (lowercase(data_file.text) == "local") {
    header_.data_local = true;
    return;
  }
  if (words[0] == "LIST" || (words.size() >= 2 && words[0].find('%') != std::string_view::npos)) {
    fail("ElementDataFile",
         "lists and numbered patterns of data files are not supported: give one data file");
  }
  header_.data_file = std::string(data_file.text);
}

MetaImageHeader Parser::parse() {
  read_lines();
  read_element_type();  // before the sizes: their overflow check depends on the sample size
  read_sizes();
  read_storage();
  read_geometry();
  read_data_file();
  return header_;
}

}  // namespace

MetaImageHeader parse_metaimage_header(std::string_view text, const std::string& file_name) {
  return Parser(text, file_name).parse();
}

}  // namespace mvox
