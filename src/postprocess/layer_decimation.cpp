#include "postprocess/layer_decimation.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "error.h"
#include "write/mesh/polygon_triangulation.h"

#if MVOX_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

namespace mvox {

namespace {

constexpr std::size_t kBatch = 4096;  // what goes downstream in one call, at most

}  // namespace

// meshopt_simplify (0.18) sometimes folds a thin part of the surface flat onto itself: two
// triangles on the same three vertices, wound opposite ways, a pocket of no volume whose edges
// are then used by four triangles. Each such pair goes: every edge of the pair is used once each
// way by the pair alone, so what remains is as closed as before, and manifold there again.
void cancel_folds(std::vector<LayerDecimation::Triangle>& triangles) {
  struct Keyed {
    std::uint64_t key[3];  // the vertices, rotated to start at the smallest
    bool reversed;         // the other winding of that rotation
    std::size_t at;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const std::uint64_t* v = triangles[t].v;
    const int first = v[0] <= v[1] && v[0] <= v[2] ? 0 : v[1] <= v[2] ? 1 : 2;
    const std::uint64_t a = v[first], b = v[(first + 1) % 3], c = v[(first + 2) % 3];
    keyed.push_back(b < c ? Keyed{{a, b, c}, false, t} : Keyed{{a, c, b}, true, t});
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& x, const Keyed& y) {
    return std::lexicographical_compare(x.key, x.key + 3, y.key, y.key + 3) ||
           (std::equal(x.key, x.key + 3, y.key) && x.reversed < y.reversed);
  });
  std::vector<bool> gone(triangles.size(), false);
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t end = i;
    while (end < keyed.size() && std::equal(keyed[i].key, keyed[i].key + 3, keyed[end].key)) ++end;
    // [i, end): one vertex set, windings sorted: pair each of one winding with one of the other.
    std::size_t forward = i, backward = i;
    while (backward < end && !keyed[backward].reversed) ++backward;
    for (; forward < end && !keyed[forward].reversed && backward < end; ++forward, ++backward)
      gone[keyed[forward].at] = gone[keyed[backward].at] = true;
    i = end;
  }
  std::size_t kept = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (!gone[t]) triangles[kept++] = triangles[t];
  triangles.resize(kept);
}

bool decimation_available() { return MVOX_HAVE_MESHOPTIMIZER != 0; }

std::uint64_t LayerDecimation::layer_bytes(std::uint32_t width, std::uint32_t height) {
  // At most three vertices a slice pixel, and five triangles (a polygon of seven corners) for
  // each, as a bound no surface reaches.
  const std::uint64_t edges = 3 * (std::uint64_t{width} + 1) * (std::uint64_t{height} + 1);
  return edges * (sizeof(Held) + 5 * sizeof(Triangle));
}

LayerDecimation::LayerDecimation(PolygonSink& downstream, const DecimationOptions& options,
                                 bool send_geometry)
    : downstream_(downstream), options_(options), send_geometry_(send_geometry) {}

Status LayerDecimation::consume_vertices(const Vertex* vertices, std::size_t vertex_count) {
  return failure_.run([&] {
    // Vertices after polygons start a layer: the one before is complete.
    if (polygons_since_vertices_) {
      polygons_since_vertices_ = false;
      if (const Status status = layer_complete(); status != Status::ok) return status;
    }
    for (std::size_t i = 0; i < vertex_count; ++i)
      vertices_.emplace(taken_ + i, Held{vertices[i], -1});
    taken_ += vertex_count;
    return Status::ok;
  });
}

Status LayerDecimation::consume_polygons(const Polygon* polygons, std::size_t polygon_count) {
  return failure_.run([&] {
    polygons_since_vertices_ = true;
    for (std::size_t p = 0; p < polygon_count; ++p) {
      const Polygon& polygon = polygons[p];
      PolygonGeometry by_value;
      std::uint64_t index[kMaxPolygonVertices];
      by_value.vertex_count = polygon.vertex_count;
      for (int k = 0; k < polygon.vertex_count; ++k) {
        index[k] = whole_vertex_index(polygon.vertices[k], taken_);
        by_value.vertices[k] = held(index[k]).vertex;
      }
      PolygonTriangles split;
      if (!triangulate_polygon(by_value, &split))
        throw Error("decimation", "internal error: a " + std::to_string(polygon.vertex_count) +
                                      "-gon cannot be split without a diagonal on a cube face");
      for (int t = 0; t < split.count; ++t)
        triangles_.push_back(
            {{index[split.corners[t][0]], index[split.corners[t][1]], index[split.corners[t][2]]}});
      triangles_in_ += static_cast<std::uint64_t>(split.count);
      new_triangles_ += static_cast<std::uint64_t>(split.count);
    }
    most_triangles_held_ = std::max(most_triangles_held_, triangles_.size());
    return Status::ok;
  });
}

Status LayerDecimation::layer_complete() {
  newest_first_ = layer_first_;
  layer_first_ = taken_;
  if (++layers_held_ < kLayersPerPass) return Status::ok;
  layers_held_ = 0;
  return pass(false);
}

Status LayerDecimation::finish() {
  return failure_.run([this] { return pass(true); });  // nothing follows: every triangle goes
}

Status LayerDecimation::pass(bool last) {
#if MVOX_HAVE_MESHOPTIMIZER
  if (!triangles_.empty()) {
    // The held part as meshoptimizer takes it: its vertices numbered from 0, positions packed.
    std::unordered_map<std::uint64_t, std::int32_t> local;
    local.reserve(2 * triangles_.size());
    std::vector<float> positions;
    std::vector<std::uint64_t> whole;
    std::vector<unsigned int> indices;
    indices.reserve(3 * triangles_.size());
    for (const Triangle& triangle : triangles_)
      for (const std::uint64_t index : triangle.v) {
        const auto [entry, added] = local.emplace(index, static_cast<std::int32_t>(whole.size()));
        const std::int32_t id = entry->second;
        if (added) {
          whole.push_back(index);
          const Vertex& vertex = held(index).vertex;
          positions.insert(positions.end(), {vertex.x, vertex.y, vertex.z});
        }
        indices.push_back(static_cast<unsigned int>(id));
      }
    // The triangles held from the last pass were reduced then: the ratio applies to the new.
    // With an error bound alone, as far as the bound allows.
    const std::uint64_t old = triangles_.size() - new_triangles_;
    const bool error_only = options_.ratio >= 1.0 && options_.max_error_voxels > 0;
    const auto target =
        error_only
            ? std::size_t{0}
            : static_cast<std::size_t>(
                  3 * (old + std::llround(options_.ratio * static_cast<double>(new_triangles_))));
    const float scale = meshopt_simplifyScale(positions.data(), whole.size(), 3 * sizeof(float));
    const float error = options_.max_error_voxels > 0 && scale > 0
                            ? static_cast<float>(options_.max_error_voxels / scale)
                            : 1.0f;  // the whole extent: no bound
    // meshopt_simplify only tries to keep the surface manifold: now and then two sheets a
    // voxel apart end up sharing an edge. The ends of every directed edge a result uses twice
    // (with the triangles already sent) are then frozen, and the pass is run again: the
    // triangles around a frozen vertex are left out of the simplification (their other
    // vertices become its border, which it keeps) and put back after it, so nothing collapses
    // onto it. Each try freezes more, so it ends; after kMaxAttempts the held triangles go as
    // they are (a valid surface). CThead at 600 needs up to a dozen on some passes.
    std::vector<unsigned int> simplified(indices.size()), input;
    std::vector<bool> frozen(whole.size(), false);
    std::vector<Triangle> result;
    std::vector<std::uint64_t> bad;
    for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
      input.clear();
      result.clear();
      for (std::size_t i = 0; i < indices.size(); i += 3) {
        const bool around_frozen =
            frozen[indices[i]] || frozen[indices[i + 1]] || frozen[indices[i + 2]];
        if (around_frozen)
          result.push_back({{whole[indices[i]], whole[indices[i + 1]], whole[indices[i + 2]]}});
        else
          input.insert(input.end(), {indices[i], indices[i + 1], indices[i + 2]});
      }
      const std::size_t wanted =
          std::min(input.size(), target > 3 * result.size() ? target - 3 * result.size() : 0);
      const std::size_t kept_indices = meshopt_simplify(
          simplified.data(), input.data(), input.size(), positions.data(), whole.size(),
          3 * sizeof(float), wanted, error, meshopt_SimplifyLockBorder, nullptr);
      for (std::size_t i = 0; i + 2 < kept_indices; i += 3)
        result.push_back(
            {{whole[simplified[i]], whole[simplified[i + 1]], whole[simplified[i + 2]]}});
      cancel_folds(result);
      bad.clear();
      if (manifold_with_sent(result, &bad)) {
        triangles_ = std::move(result);
        break;
      }
      ++retried_passes_;
      for (const std::uint64_t index : bad) {
        const auto entry = local.find(index);
        if (entry != local.end()) frozen[static_cast<std::size_t>(entry->second)] = true;
      }
    }
  }
#endif
  new_triangles_ = 0;
  // Later triangles can share only the newest complete layer's vertices (and the arriving
  // layer's): the triangles that touch them stay for the next pass, the rest go.
  std::vector<Triangle> going, staying;
  for (const Triangle& triangle : triangles_) {
    const bool touches_newest =
        !last && (triangle.v[0] >= newest_first_ || triangle.v[1] >= newest_first_ ||
                  triangle.v[2] >= newest_first_);
    (touches_newest ? staying : going).push_back(triangle);
  }
  triangles_ = std::move(staying);
  if (const Status status = send(going); status != Status::ok) return status;
  forget_unused();
  return Status::ok;
}

bool LayerDecimation::manifold_with_sent(const std::vector<Triangle>& triangles,
                                         std::vector<std::uint64_t>* bad) const {
  std::unordered_set<DirectedEdge, DirectedEdgeHash> edges;
  edges.reserve(3 * triangles.size());
  for (const Triangle& triangle : triangles)
    for (int k = 0; k < 3; ++k) {
      const DirectedEdge edge{triangle.v[k], triangle.v[(k + 1) % 3]};
      if (!edges.insert(edge).second || sent_edges_.count(edge) > 0)
        bad->insert(bad->end(), {edge.from, edge.to});
    }
  return bad->empty();
}

Status LayerDecimation::send(const std::vector<Triangle>& triangles) {
  // Their vertices first, numbered anew in the order they are first used.
  std::vector<Vertex> batch;
  for (const Triangle& triangle : triangles)
    for (const std::uint64_t index : triangle.v) {
      Held& vertex = held(index);
      if (vertex.sent_as >= 0) continue;
      vertex.sent_as = static_cast<std::int64_t>(vertices_out_++);
      batch.push_back(vertex.vertex);
      if (batch.size() == kBatch) {
        if (const Status status = downstream_.consume_vertices(batch.data(), batch.size());
            status != Status::ok)
          return status;
        batch.clear();
      }
    }
  if (!batch.empty())
    if (const Status status = downstream_.consume_vertices(batch.data(), batch.size());
        status != Status::ok)
      return status;
  std::vector<Polygon> polygons;
  std::vector<PolygonGeometry> geometry;
  for (std::size_t first = 0; first < triangles.size(); first += kBatch) {
    const std::size_t end = std::min(triangles.size(), first + kBatch);
    polygons.assign(end - first, Polygon());
    geometry.assign(send_geometry_ ? end - first : 0, PolygonGeometry());
    for (std::size_t t = first; t < end; ++t) {
      Polygon& polygon = polygons[t - first];
      polygon.vertex_count = 3;
      for (int k = 0; k < 3; ++k) {
        const Held& vertex = held(triangles[t].v[k]);
        polygon.vertices[k] = static_cast<std::uint32_t>(vertex.sent_as);  // modulo 2^32
        if (send_geometry_) geometry[t - first].vertices[k] = vertex.vertex;
      }
      if (send_geometry_) geometry[t - first].vertex_count = 3;
    }
    if (const Status status = downstream_.consume_polygons(polygons.data(), polygons.size());
        status != Status::ok)
      return status;
    if (send_geometry_)
      if (const Status status =
              downstream_.consume_polygon_geometry(geometry.data(), geometry.size());
          status != Status::ok)
        return status;
  }
  triangles_out_ += triangles.size();
  for (const Triangle& triangle : triangles)
    for (int k = 0; k < 3; ++k) sent_edges_.insert({triangle.v[k], triangle.v[(k + 1) % 3]});
  return Status::ok;
}

// Vertices no held triangle uses and no later polygon can (older than the newest complete
// layer) are let go, wherever they are: a held triangle may join a vertex of an old, locked
// border to the newest layer pass after pass (a long flat stretch), and keeping every vertex in
// between made memory grow with the slices.
void LayerDecimation::forget_unused() {
  std::unordered_set<std::uint64_t> used;
  used.reserve(3 * triangles_.size());
  for (const Triangle& triangle : triangles_) used.insert(triangle.v, triangle.v + 3);
  for (auto vertex = vertices_.begin(); vertex != vertices_.end();)
    vertex = vertex->first < newest_first_ && used.count(vertex->first) == 0
                 ? vertices_.erase(vertex)
                 : std::next(vertex);
  // Sent edges matter while a later triangle could repeat them: both ends still held.
  for (auto edge = sent_edges_.begin(); edge != sent_edges_.end();)
    edge = vertices_.count(edge->from) == 0 || vertices_.count(edge->to) == 0
               ? sent_edges_.erase(edge)
               : std::next(edge);
  most_vertices_held_ = std::max(most_vertices_held_, vertices_.size());
}

}  // namespace mvox
