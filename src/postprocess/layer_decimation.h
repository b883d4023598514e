#pragma once
// --decimate RATIO / --max-error E: the surface simplified as it streams, in bounded memory.
//
// A PolygonSink between the engine (or the smoothing) and the writers and renderer. Polygons are
// split into triangles (polygon_triangulation.h) and held; every kLayersPerPass layers, the held
// triangles are simplified by meshoptimizer's meshopt_simplify (edge collapses onto existing
// vertices, so every vertex keeps its place) with the held part's border locked: the border is
// where the held triangles meet triangles already sent, or triangles still to come. Then the
// triangles that touch the newest layer's vertices (the only ones later triangles can share)
// stay held and are simplified again with the next pass, so the seams between passes are
// simplified too; the rest go downstream, with the vertices they use, numbered anew in the
// order they are first used. Memory: the triangles and vertices of about kLayersPerPass layers,
// a function of the slice size, never of the number of slices.
//
// Collapses that would break the surface are not made: the result stays closed and manifold
// (layer_decimation_test checks on phantoms).
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mvox/polygon_sink.h"
#include "postprocess/stage_failure.h"

namespace mvox {

struct DecimationOptions {
  // The share of triangles to keep (0 < ratio <= 1); 1 with max_error alone.
  double ratio = 1.0;
  // The largest distance, in voxels, a simplification may move the surface by; 0: as the ratio
  // needs.
  double max_error_voxels = 0.0;
};

// Whether this build can decimate (it was built with meshoptimizer).
bool decimation_available();

class LayerDecimation : public PolygonSink {
 public:
  struct Triangle {
    std::uint64_t v[3];  // whole indices, as the engine numbers them
  };

  static constexpr std::uint32_t kLayersPerPass = 16;
  static constexpr int kMaxAttempts = 64;  // simplifications of one pass (see pass())

  // `downstream` gets the simplified mesh, triangles only; with `send_geometry` each triangle
  // by value too (a renderer's, STL's).
  LayerDecimation(PolygonSink& downstream, const DecimationOptions& options, bool send_geometry);

  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override;
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override;
  // Polygons by value are remade from the vertices.
  Status consume_polygon_geometry(const PolygonGeometry*, std::size_t) override {
    return Status::ok;
  }

  // An upper bound of the memory one layer held takes for slices of width x height (the memory
  // plan's; a real surface uses a small part of it).
  static std::uint64_t layer_bytes(std::uint32_t width, std::uint32_t height);

  // After the last layer: simplifies and sends what is held.
  Status finish();

  std::exception_ptr thrown() const { return failure_.thrown(); }
  std::uint64_t triangles_in() const { return triangles_in_; }
  std::uint64_t triangles_out() const { return triangles_out_; }
  std::uint64_t vertices_out() const { return vertices_out_; }
  // The most triangles held at once, for tests.
  std::size_t most_triangles_held() const { return most_triangles_held_; }
  // The most vertices held after a pass, for tests.
  std::size_t most_vertices_held() const { return most_vertices_held_; }
  // Simplifications not taken because they broke the surface (each then run again with the
  // vertices where it broke frozen).
  std::uint64_t retried_passes() const { return retried_passes_; }

 private:
  struct Held {
    Vertex vertex;
    std::int64_t sent_as = -1;  // its index downstream, once sent
  };

  Status layer_complete();
  Status pass(bool last);
  Status send(const std::vector<Triangle>& triangles);
  // True when `triangles` use no directed edge twice, among them or with those already sent;
  // else false, with the ends of each edge used twice added to `bad`.
  bool manifold_with_sent(const std::vector<Triangle>& triangles,
                          std::vector<std::uint64_t>* bad) const;
  Held& held(std::uint64_t index) { return vertices_.at(index); }
  void forget_unused();

  PolygonSink& downstream_;
  DecimationOptions options_;
  bool send_geometry_;
  // By whole index: those held triangles use, and all from the newest complete layer on.
  std::unordered_map<std::uint64_t, Held> vertices_;
  std::size_t most_vertices_held_ = 0;
  std::uint64_t taken_ = 0;
  std::uint64_t layer_first_ = 0;   // first vertex of the layer arriving
  std::uint64_t newest_first_ = 0;  // first vertex of the newest complete layer
  bool polygons_since_vertices_ = false;
  std::uint32_t layers_held_ = 0;
  std::vector<Triangle> triangles_;  // held
  std::uint64_t new_triangles_ = 0;  // of them, not through a pass yet
  std::uint64_t triangles_in_ = 0, triangles_out_ = 0, vertices_out_ = 0;
  std::size_t most_triangles_held_ = 0;
  std::uint64_t retried_passes_ = 0;
  struct DirectedEdge {
    std::uint64_t from, to;
    bool operator==(const DirectedEdge& other) const {
      return from == other.from && to == other.to;
    }
  };
  struct DirectedEdgeHash {
    std::size_t operator()(const DirectedEdge& edge) const {
      return std::hash<std::uint64_t>()(edge.from * 0x9E3779B97F4A7C15ull ^ edge.to);
    }
  };
  // The directed edges of the triangles sent whose two ends are still held.
  std::unordered_set<DirectedEdge, DirectedEdgeHash> sent_edges_;
  StageFailure failure_;
};

// Removes the pairs of triangles on the same three vertices wound opposite ways (folds of no
// volume a simplification may leave); what remains is as closed as before.
void cancel_folds(std::vector<LayerDecimation::Triangle>& triangles);

}  // namespace mvox
