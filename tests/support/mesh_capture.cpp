#include "mesh_capture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include "mvox/stream_volume.h"

namespace mvox::test {

Status MeshCapture::consume_vertices(const Vertex* vertices, std::size_t vertex_count) {
  ++vertex_batches;
  mesh.vertices.insert(mesh.vertices.end(), vertices, vertices + vertex_count);
  return Status::ok;
}

Status MeshCapture::consume_polygons(const Polygon* polygons, std::size_t polygon_count) {
  ++polygon_batches;
  for (std::size_t i = 0; i < polygon_count; ++i) {
    const Polygon& p = polygons[i];
    std::vector<std::uint32_t> indices(p.vertices, p.vertices + p.vertex_count);
    for (std::uint32_t index : indices)
      if (index >= mesh.vertices.size()) ++mesh.forward_references;
    mesh.polygons.push_back(std::move(indices));
  }
  return Status::ok;
}

Status MeshCapture::consume_polygon_geometry(const PolygonGeometry* polygons,
                                             std::size_t polygon_count) {
  geometry.insert(geometry.end(), polygons, polygons + polygon_count);
  return Status::ok;
}

Mesh extract_slices(const std::vector<SliceView>& slices, std::uint32_t width, std::uint32_t height,
                    double threshold, const EngineOptions& options, EngineCounters* counters) {
  MeshCapture capture;
  Workspace workspace(engine_workspace_bytes(width, height, options));
  Engine engine;
  EXPECT_EQ(
      engine.init(workspace.data(), workspace.bytes(), width, height, threshold, options, &capture),
      Status::ok);
  for (std::size_t z = 0; z < slices.size(); ++z)
    EXPECT_EQ(engine.push_slice(slices[z]), Status::ok) << "slice " << z;
  EXPECT_EQ(engine.finish(), Status::ok);
  if (counters) *counters = engine.counters();
  return std::move(capture.mesh);
}

template <typename Sample>
Mesh extract(const Volume<Sample>& volume, double threshold, const EngineOptions& options,
             EngineCounters* counters) {
  SampleType type = SampleType::u8;
  if constexpr (std::is_same_v<Sample, std::uint16_t>) type = SampleType::u16;
  if constexpr (std::is_same_v<Sample, std::int16_t>) type = SampleType::i16;
  if constexpr (std::is_same_v<Sample, float>) type = SampleType::f32;
  std::vector<SliceView> slices;
  for (std::uint32_t z = 0; z < volume.depth; ++z)
    slices.push_back({volume.samples.data() + std::size_t{z} * volume.width * volume.height,
                      volume.width, volume.height, volume.width * sizeof(Sample), type});
  return extract_slices(slices, volume.width, volume.height, threshold, options, counters);
}

template Mesh extract(const Volume<std::uint8_t>&, double, const EngineOptions&, EngineCounters*);
template Mesh extract(const Volume<std::uint16_t>&, double, const EngineOptions&, EngineCounters*);
template Mesh extract(const Volume<std::int16_t>&, double, const EngineOptions&, EngineCounters*);
template Mesh extract(const Volume<float>&, double, const EngineOptions&, EngineCounters*);

EngineCounters stream_into(SliceSource& source, double threshold, PolygonSink& sink,
                           const EngineOptions& options, SliceProgress progress) {
  const VolumeInfo& info = source.info();
  Workspace workspace(engine_workspace_bytes(info.width, info.height, options));
  Engine engine;
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), info.width, info.height, threshold,
                        options, &sink),
            Status::ok);
  EXPECT_EQ(stream_volume(source, engine, progress), Status::ok);
  return engine.counters();
}

Mesh extract(SliceSource& source, double threshold, const EngineOptions& options,
             EngineCounters* counters) {
  MeshCapture capture;
  const EngineCounters engine_counters = stream_into(source, threshold, capture, options);
  if (counters) *counters = engine_counters;
  return std::move(capture.mesh);
}

namespace {
bool position_less(const Vertex& a, const Vertex& b) {
  return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
}
}  // namespace

bool same_position(const Vertex& a, const Vertex& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

std::vector<Vertex> expected_vertices(const BinaryVolume& volume) {
  auto inner = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    if (x < 0 || y < 0 || z < 0 || x >= volume.width || y >= volume.height || z >= volume.depth)
      return false;
    return volume.at(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                     static_cast<std::uint32_t>(z)) != 0;
  };
  std::vector<Vertex> vertices;
  for (std::int64_t z = -1; z < volume.depth; ++z)
    for (std::int64_t y = -1; y < volume.height; ++y)
      for (std::int64_t x = -1; x < volume.width; ++x) {
        const bool here = inner(x, y, z);
        const std::int64_t step[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (const auto& d : step)
          if (here != inner(x + d[0], y + d[1], z + d[2])) {
            Vertex v;
            v.x = static_cast<float>(x) + 0.5f * static_cast<float>(d[0]);
            v.y = static_cast<float>(y) + 0.5f * static_cast<float>(d[1]);
            v.z = static_cast<float>(z) + 0.5f * static_cast<float>(d[2]);
            vertices.push_back(v);
          }
      }
  std::sort(vertices.begin(), vertices.end(), position_less);
  return vertices;
}

std::vector<Vertex> sorted_positions(const Mesh& mesh) {
  std::vector<Vertex> vertices = mesh.vertices;
  std::sort(vertices.begin(), vertices.end(), position_less);
  return vertices;
}

BinaryVolume volume_from_bits(std::uint32_t w, std::uint32_t h, std::uint32_t d,
                              std::uint64_t bits) {
  BinaryVolume volume(w, h, d);
  for (std::size_t i = 0; i < volume.samples.size(); ++i) volume.samples[i] = bits >> i & 1;
  return volume;
}

Volume<std::uint8_t> noise_volume(std::uint32_t w, std::uint32_t h, std::uint32_t d,
                                  std::uint32_t seed) {
  Volume<std::uint8_t> volume(w, h, d);
  std::mt19937 generator(seed);
  for (auto& sample : volume.samples) sample = static_cast<std::uint8_t>(generator() >> 24);
  return volume;
}

SliceView slice_of(const BinaryVolume& volume, std::uint32_t z) {
  SliceView slice;
  slice.samples = volume.samples.data() + std::size_t{z} * volume.width * volume.height;
  slice.width = volume.width;
  slice.height = volume.height;
  slice.row_stride_bytes = volume.width;
  return slice;
}

}  // namespace mvox::test
