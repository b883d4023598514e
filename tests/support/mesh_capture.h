#pragma once
// Test support: run the engine over a volume held in memory (or any slice source) and keep the
// whole mesh, checking as it arrives that polygons only use vertices already delivered.
#include <cstdint>
#include <vector>

#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "mvox/stream_volume.h"
#include "mvox/workspace_buffer.h"

namespace mvox::test {

struct Mesh {
  std::vector<Vertex> vertices;
  std::vector<std::vector<std::uint32_t>> polygons;
  std::size_t forward_references = 0;  // polygon indices not yet delivered when it arrived
};

class MeshCapture : public PolygonSink {
 public:
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override;
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override;
  // Polygons by value, when the source sends them (EngineOptions::polygon_geometry, or a stage
  // that remakes them).
  Status consume_polygon_geometry(const PolygonGeometry* polygons,
                                  std::size_t polygon_count) override;
  Mesh mesh;
  std::vector<PolygonGeometry> geometry;
  std::size_t vertex_batches = 0;
  std::size_t polygon_batches = 0;
};

// A dense volume, x fastest: samples[(z * height + y) * width + x].
template <typename Sample>
struct Volume {
  std::uint32_t width = 0, height = 0, depth = 0;
  std::vector<Sample> samples;
  Volume(std::uint32_t w, std::uint32_t h, std::uint32_t d)
      : width(w), height(h), depth(d), samples(std::size_t{w} * h * d) {}
  Sample& at(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return samples[(std::size_t{z} * height + y) * width + x];
  }
  Sample at(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return samples[(std::size_t{z} * height + y) * width + x];
  }
};
using BinaryVolume = Volume<std::uint8_t>;

using Workspace = WorkspaceBuffer;

// Extracts the surface of `volume` (inner: sample >= threshold). Fails the current test on any
// engine error.
template <typename Sample>
Mesh extract(const Volume<Sample>& volume, double threshold, const EngineOptions& options = {},
             EngineCounters* counters = nullptr);

Mesh extract(SliceSource& source, double threshold, const EngineOptions& options = {},
             EngineCounters* counters = nullptr);

// Streams `source` through a new engine into `sink` (stream_volume), `progress` told after each
// slice; returns the engine's counters. Fails the current test on any engine error.
EngineCounters stream_into(SliceSource& source, double threshold, PolygonSink& sink,
                           const EngineOptions& options = {}, SliceProgress progress = {});

// Extracts the surface of the given slices, pushed in order, all `width` x `height`.
Mesh extract_slices(const std::vector<SliceView>& slices, std::uint32_t width, std::uint32_t height,
                    double threshold, const EngineOptions& options = {},
                    EngineCounters* counters = nullptr);

// Every inner/outer pair of 6-adjacent voxels (voxels outside the volume are outer), as the
// midpoint the vertex must sit at, sorted: an oracle independent of the engine.
std::vector<Vertex> expected_vertices(const BinaryVolume& inner);

// Vertex positions of a mesh, sorted like expected_vertices().
std::vector<Vertex> sorted_positions(const Mesh& mesh);

bool same_position(const Vertex& a, const Vertex& b);

// A volume whose voxels are 1 where the bits of `bits` are set, bit i = voxel i in x-fastest order.
BinaryVolume volume_from_bits(std::uint32_t w, std::uint32_t h, std::uint32_t d,
                              std::uint64_t bits);

// A reproducible volume of 8-bit samples 0..255 (raw generator bits; no distributions, whose
// output differs between standard libraries).
Volume<std::uint8_t> noise_volume(std::uint32_t w, std::uint32_t h, std::uint32_t d,
                                  std::uint32_t seed);

// Slice `z` of an 8-bit volume, as the engine takes it (rows packed).
SliceView slice_of(const BinaryVolume& volume, std::uint32_t z);

}  // namespace mvox::test
