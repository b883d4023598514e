#include "obj_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "ply_mesh.h"    // mesh_of_positions
#include "stl_reader.h"  // read_file_bytes

namespace mvox::test {
namespace {

std::vector<std::string> fields_of(const std::string& line, std::size_t line_number) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t space = line.find(' ', start);
    const std::string field = line.substr(start, space - start);
    if (field.empty())
      throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": empty field");
    fields.push_back(field);
    if (space == std::string::npos) return fields;
    start = space + 1;
  }
}

float parse_float(const std::string& text, std::size_t line_number) {
  char* end = nullptr;
  errno = 0;
  const float value = std::strtof(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno != 0 || !std::isfinite(value))
    throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": \"" + text +
                             "\" is not a finite float");
  return value;
}

// A 1-based index among `available` items, returned 0-based.
std::uint32_t parse_index(const std::string& text, std::size_t available, std::size_t line_number) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text[0] == '0')
    throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": \"" + text +
                             "\" is not a positive index");
  const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (value > available)
    throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": index " + text +
                             " beyond the " + std::to_string(available) + " defined so far");
  return static_cast<std::uint32_t>(value - 1);
}

}  // namespace

ObjFile parse_obj(const std::string& text) {
  ObjFile obj;
  bool data_seen = false;
  std::size_t line_number = 0;
  for (std::size_t start = 0; start < text.size();) {
    ++line_number;
    const std::size_t newline = text.find('\n', start);
    if (newline == std::string::npos)
      throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": no line end");
    const std::string line = text.substr(start, newline - start);
    start = newline + 1;
    if (line.rfind("# ", 0) == 0) {
      obj.comments.push_back(line.substr(2));
      if (data_seen) obj.comments_first = false;
      continue;
    }
    data_seen = true;
    const std::vector<std::string> fields = fields_of(line, line_number);
    const std::string& keyword = fields[0];
    if (keyword == "v" || keyword == "vn") {
      if (fields.size() != 4)
        throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": " + keyword +
                                 " needs 3 numbers");
      std::array<float, 3> value;
      for (int i = 0; i < 3; ++i) value[i] = parse_float(fields[1 + i], line_number);
      (keyword == "v" ? obj.positions : obj.normals).push_back(value);
    } else if (keyword == "f") {
      if (fields.size() < 4)
        throw std::runtime_error("OBJ line " + std::to_string(line_number) +
                                 ": a face needs 3 corners");
      std::vector<std::uint32_t> face, normals;
      const bool with_normals = fields[1].find("//") != std::string::npos;
      for (std::size_t k = 1; k < fields.size(); ++k) {
        const std::string& corner = fields[k];
        const std::size_t slashes = corner.find("//");
        if ((slashes != std::string::npos) != with_normals)
          throw std::runtime_error("OBJ line " + std::to_string(line_number) +
                                   ": corners of mixed forms");
        face.push_back(parse_index(corner.substr(0, slashes), obj.positions.size(), line_number));
        if (with_normals)
          normals.push_back(
              parse_index(corner.substr(slashes + 2), obj.normals.size(), line_number));
      }
      obj.faces.push_back(face);
      obj.face_normals.push_back(normals);
    } else {
      throw std::runtime_error("OBJ line " + std::to_string(line_number) + ": unknown \"" +
                               keyword + "\"");
    }
  }
  return obj;
}

ObjFile read_obj(const std::string& path) { return parse_obj(read_file_bytes(path)); }

Mesh to_mesh(const ObjFile& obj) {
  Mesh mesh = mesh_of_positions(obj.positions);
  mesh.polygons = obj.faces;
  return mesh;
}

}  // namespace mvox::test
