#pragma once
// --smooth N: the surface smoothed as it streams, each vertex held on its own voxel edge.
//
// A PolygonSink between the engine and the writers and renderer. Each vertex may move only
// along the axis of its voxel pair, within the segment between the two voxel centres (0.01
// voxel short of each), so the smoothed surface still separates the same inner and outer
// voxels, and the polygons, their indices and so the closed surface are the engine's. A vertex
// between a voxel and the outside of the volume stays where the engine put it.
//
// Each iteration moves a vertex by what corrects its offset from the mean of its neighbours
// *across* the surface: s = 0.6 n.(mean - p) / n[axis], n the normal of the faces around it
// (|n[axis]| taken as at least 0.2). A plain Laplacian step (the axis component of the offset)
// stalls: a vertex held on its axis cannot follow the tangential part of the pull
// (bench/smoothing_schemes.py).
//
// The stream: the engine sends, for each slice z, the vertices of that slice's layer, then the
// polygons of the cube layer it completes (which use the vertices of layers z - 1 and z). A
// vertex of layer z is used by the polygons of cube layers z and z + 1, so its first iteration
// can run once layer z + 1 has arrived, and iteration k once layer z + k has. When a layer
// arrives (end_layer()), the N layers before it each advance one iteration, newest first, and
// the layer before those, final, goes downstream with its polygons. Memory: N + 3 layers of
// vertices and polygons, a function of the slice size and N, never of the number of slices.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <vector>

#include "mvox/polygon_sink.h"
#include "mvox/slice_source.h"
#include "postprocess/stage_failure.h"

namespace mvox {

class EdgeSmoothing : public PolygonSink {
 public:
  static constexpr float kStep = 0.6f;
  static constexpr float kMargin = 0.01f;  // kept from each voxel centre, in voxels
  static constexpr float kMinAxisNormal = 0.2f;

  // `volume`: width, height and depth, for the border. `downstream` gets the smoothed mesh;
  // with `send_geometry` each polygon by value too (a renderer's, STL's), at the smoothed
  // positions. `iterations` >= 1.
  EdgeSmoothing(PolygonSink& downstream, const VolumeInfo& volume, std::uint32_t iterations,
                bool send_geometry);

  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override;
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override;
  // The engine's polygons by value are not used: they are remade at the smoothed positions.
  Status consume_polygon_geometry(const PolygonGeometry*, std::size_t) override {
    return Status::ok;
  }

  // The layer of the slice the engine has just taken is complete: advances the layers before it
  // and sends the final one downstream. Call after each slice (SliceProgress).
  Status end_layer();
  // After the engine's finish(): the last layer is complete; every layer is smoothed to the end
  // and sent.
  Status finish();

  // An upper bound of the memory one held layer takes for slices of width x height: every
  // voxel edge of a slice carrying a vertex, each with its two coordinates kept, and as many
  // polygons (for the memory plan; a real surface uses a small part of it).
  static std::uint64_t layer_bytes(std::uint32_t width, std::uint32_t height);

  // What stopped it: an exception thrown inside (rethrown by the caller) or downstream's status.
  std::exception_ptr thrown() const { return failure_.thrown(); }
  // The most layers held at once, for memory reports and tests.
  std::size_t most_layers_held() const { return most_layers_held_; }

 private:
  struct Layer {
    std::uint64_t first_vertex = 0;  // whole index of its first vertex
    std::vector<Vertex> vertices;    // as the engine made them
    std::vector<float> current;      // each vertex's coordinate along its axis, as smoothed
    std::vector<float> previous;     // the same one iteration before, once it has advanced
    std::vector<Polygon> polygons;   // the cube layer it completes
  };

  Status arrive();  // the newest layer is complete
  void advance(std::size_t layer);
  Status send(std::size_t layer_index);  // sends layers_[layer_index], final
  std::size_t layer_of(std::uint64_t index, std::size_t near) const;

  PolygonSink& downstream_;
  std::uint32_t size_[3];
  std::uint32_t iterations_;
  bool send_geometry_;
  std::deque<Layer> layers_;  // oldest first; the last is the one arriving
  std::uint64_t vertices_taken_ = 0;
  std::size_t most_layers_held_ = 0;
  StageFailure failure_;
  // Scratch of advance(), kept between calls.
  std::vector<double> around_, sums_, normals_;
  std::vector<float> next_;
  std::vector<std::uint32_t> counts_;
  std::vector<Vertex> out_vertices_;
  std::vector<PolygonGeometry> out_geometry_;
};

}  // namespace mvox
