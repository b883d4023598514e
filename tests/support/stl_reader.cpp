#include "stl_reader.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace mvox::test {
namespace {

std::uint32_t load_le32(const unsigned char* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}

float load_float(const unsigned char* p) {
  const std::uint32_t bits = load_le32(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  if (!std::isfinite(value)) throw std::runtime_error("STL: a float is not finite");
  return value;
}

}  // namespace

std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

StlFile parse_stl(const std::string& bytes) {
  if (bytes.size() < 84)
    throw std::runtime_error("STL: " + std::to_string(bytes.size()) + " bytes, less than 84");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  StlFile stl;
  stl.header = bytes.substr(0, 80);
  const std::uint64_t count = load_le32(data + 80);
  if (bytes.size() != 84 + 50 * count)
    throw std::runtime_error("STL: " + std::to_string(bytes.size()) + " bytes for " +
                             std::to_string(count) + " triangles, expected " +
                             std::to_string(84 + 50 * count));
  stl.triangles.resize(count);
  for (std::uint64_t t = 0; t < count; ++t) {
    const unsigned char* record = data + 84 + 50 * t;
    StlTriangle& triangle = stl.triangles[t];
    for (int i = 0; i < 3; ++i) triangle.normal[i] = load_float(record + 4 * i);
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i)
        triangle.vertices[k][i] = load_float(record + 12 + 12 * k + 4 * i);
    triangle.attribute = static_cast<std::uint16_t>(record[48] | record[49] << 8);
  }
  return stl;
}

StlFile read_stl(const std::string& path) { return parse_stl(read_file_bytes(path)); }

std::string normal_problems(const StlFile& stl) {
  for (std::size_t t = 0; t < stl.triangles.size(); ++t) {
    const StlTriangle& triangle = stl.triangles[t];
    const auto& p = triangle.vertices;
    double u[3], v[3];
    for (int i = 0; i < 3; ++i) {
      u[i] = double{p[1][i]} - p[0][i];
      v[i] = double{p[2][i]} - p[0][i];
    }
    const double cross[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                             u[0] * v[1] - u[1] * v[0]};
    const double area2 = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    const auto& n = triangle.normal;
    const double length =
        std::sqrt(double{n[0]} * n[0] + double{n[1]} * n[1] + double{n[2]} * n[2]);
    std::ostringstream problem;
    problem << "triangle " << t << ": normal (" << n[0] << ", " << n[1] << ", " << n[2] << ")";
    if (area2 == 0.0) {
      if (length != 0.0) return problem.str() + " for a triangle without area";
      continue;
    }
    if (std::fabs(length - 1.0) > 1e-5) return problem.str() + " is not a unit vector";
    const double agreement = (cross[0] * n[0] + cross[1] * n[1] + cross[2] * n[2]) / area2;
    if (agreement < 1.0 - 1e-5) {
      problem << " disagrees with the winding (cosine " << agreement << ")";
      return problem.str();
    }
  }
  return {};
}

Mesh welded(const StlFile& stl) {
  Mesh mesh;
  std::map<Float3, std::uint32_t> index_of;
  for (const StlTriangle& triangle : stl.triangles) {
    std::vector<std::uint32_t> face;
    for (const Float3& p : triangle.vertices) {
      const auto [it, added] =
          index_of.emplace(p, static_cast<std::uint32_t>(mesh.vertices.size()));
      if (added) {
        Vertex v;
        v.x = p[0];
        v.y = p[1];
        v.z = p[2];
        mesh.vertices.push_back(v);
      }
      face.push_back(it->second);
    }
    mesh.polygons.push_back(face);
  }
  return mesh;
}

}  // namespace mvox::test
