#pragma once
// A polygon sink for the firmware demo: it keeps nothing but counts and two checksums of the
// engine's output, so that two builds (the host's and the board's) can be compared by a few
// numbers. Allocates nothing.
//
// Each checksum is 64-bit FNV-1a over the records in the order the engine emits them, every
// record written in a fixed little-endian layout whatever the platform:
//   vertex record, 14 bytes:  x, y, z as IEEE-754 binary32 bit patterns, 4 bytes each,
//                             least significant byte first; then the axis (0 = x, 1 = y,
//                             2 = z); then inner_is_lower (0 or 1).
//   polygon record, 1 + 4n:   the vertex count n, then the n vertex indices as unsigned
//                             32-bit integers, least significant byte first.
// Vertices and polygons have a checksum each, so neither depends on how the engine cuts its
// output into batches (which follows EngineOptions::vertices_per_batch and polygons_per_batch).
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "mvox/mesh.h"
#include "mvox/polygon_sink.h"

namespace mvox::firmware {

class Fnv1a64 {
 public:
  void byte(std::uint8_t value) { hash_ = (hash_ ^ value) * 0x100000001b3ull; }
  void u32_le(std::uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) byte(static_cast<std::uint8_t>(value >> shift));
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;  // the FNV-1a 64-bit offset basis
};

class ChecksumSink final : public PolygonSink {
 public:
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    for (std::size_t i = 0; i < vertex_count; ++i) {
      const Vertex& v = vertices[i];
      const float coordinates[3] = {v.x, v.y, v.z};
      for (const float coordinate : coordinates) {
        std::uint32_t bits;
        static_assert(sizeof bits == sizeof coordinate, "binary32 floats");
        std::memcpy(&bits, &coordinate, sizeof bits);
        vertex_checksum_.u32_le(bits);
      }
      vertex_checksum_.byte(static_cast<std::uint8_t>(v.axis));
      vertex_checksum_.byte(v.inner_is_lower ? 1 : 0);
    }
    vertices_ += vertex_count;
    return Status::ok;
  }

  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    for (std::size_t i = 0; i < polygon_count; ++i) {
      const Polygon& polygon = polygons[i];
      const int n = polygon.vertex_count;
      if (n < 3 || n > kMaxPolygonVertices) {
        ++broken_polygons_;  // not a polygon the engine may emit
        continue;
      }
      ++polygons_by_size_[n];
      polygon_checksum_.byte(static_cast<std::uint8_t>(n));
      for (int k = 0; k < n; ++k) {
        // The engine's contract: every vertex arrives before the first polygon that uses it.
        if (polygon.vertices[k] >= vertices_) ++broken_polygons_;
        polygon_checksum_.u32_le(polygon.vertices[k]);
      }
    }
    polygons_ += polygon_count;
    return Status::ok;
  }

  std::uint64_t vertices() const { return vertices_; }
  std::uint64_t polygons() const { return polygons_; }
  // Polygons of n vertices, n = 3 .. kMaxPolygonVertices.
  std::uint64_t polygons_of_size(int n) const { return polygons_by_size_[n]; }
  // Polygons with an impossible vertex count, or with an index not yet emitted: must be 0.
  std::uint64_t broken_polygons() const { return broken_polygons_; }
  std::uint64_t vertex_checksum() const { return vertex_checksum_.value(); }
  std::uint64_t polygon_checksum() const { return polygon_checksum_.value(); }

 private:
  std::uint64_t vertices_ = 0;
  std::uint64_t polygons_ = 0;
  std::uint64_t polygons_by_size_[kMaxPolygonVertices + 1] = {};
  std::uint64_t broken_polygons_ = 0;
  Fnv1a64 vertex_checksum_;
  Fnv1a64 polygon_checksum_;
};

}  // namespace mvox::firmware
