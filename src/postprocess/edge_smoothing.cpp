#include "postprocess/edge_smoothing.h"

#include <algorithm>
#include <cmath>

namespace mvox {

namespace {

constexpr std::size_t kBatch = 4096;  // what goes downstream in one call, at most

int axis_of(const Vertex& vertex) { return static_cast<int>(vertex.axis); }

// The lower voxel centre of the vertex's pair, along its axis. The engine's vertex lies on
// [lower, lower + 1]: at the midpoint, or interpolated towards the outer voxel, reaching the
// inner one only when its sample equals the threshold.
float lower_end(const Vertex& vertex) {
  const float c = along_axis(vertex);
  return vertex.inner_is_lower ? std::floor(c) : std::ceil(c) - 1.0f;
}

}  // namespace

EdgeSmoothing::EdgeSmoothing(PolygonSink& downstream, const VolumeInfo& volume,
                             std::uint32_t iterations, bool send_geometry)
    : downstream_(downstream),
      size_{volume.width, volume.height, volume.depth},
      iterations_(iterations),
      send_geometry_(send_geometry) {
  layers_.emplace_back();
}

Status EdgeSmoothing::consume_vertices(const Vertex* vertices, std::size_t vertex_count) {
  return failure_.run([&] {
    Layer& layer = layers_.back();
    layer.vertices.insert(layer.vertices.end(), vertices, vertices + vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) layer.current.push_back(along_axis(vertices[i]));
    vertices_taken_ += vertex_count;
    return Status::ok;
  });
}

Status EdgeSmoothing::consume_polygons(const Polygon* polygons, std::size_t polygon_count) {
  return failure_.run([&] {
    Layer& layer = layers_.back();
    layer.polygons.insert(layer.polygons.end(), polygons, polygons + polygon_count);
    return Status::ok;
  });
}

std::uint64_t EdgeSmoothing::layer_bytes(std::uint32_t width, std::uint32_t height) {
  // At most three vertices a slice pixel (its x-, y- and z-edges; the borders add a row and a
  // column) and, as a bound that no surface reaches, as many polygons.
  const std::uint64_t edges = 3 * (std::uint64_t{width} + 1) * (std::uint64_t{height} + 1);
  return edges * (sizeof(Vertex) + 2 * sizeof(float) + sizeof(Polygon));
}

Status EdgeSmoothing::end_layer() {
  return failure_.run([this] { return arrive(); });
}

Status EdgeSmoothing::finish() {
  // The engine's closing layer, then as many empty ones as it takes for the last real layer to
  // reach the last iteration and leave.
  for (std::uint32_t step = 0; step <= iterations_ + 1; ++step)
    if (const Status status = end_layer(); status != Status::ok) return status;
  return Status::ok;
}

Status EdgeSmoothing::arrive() {
  const std::size_t newest = layers_.size() - 1;
  // Layer newest - j goes from iteration j - 1 to j, newest first: the layer above it has then
  // reached iteration j - 1 too, and the layer below it still keeps that iteration as
  // `previous`.
  for (std::uint32_t j = 1; j <= iterations_ && j <= newest; ++j) advance(newest - j);
  // The layer below those is final: it leaves, and what it no longer needs goes.
  if (newest >= iterations_ + 1) {
    // Each layer comes to this place once.
    if (const Status status = send(newest - iterations_ - 1); status != Status::ok) return status;
    // Kept: the final layer (the next one to leave uses its vertices) and those above.
    while (layers_.size() > iterations_ + 2) layers_.pop_front();
  }
  most_layers_held_ = std::max(most_layers_held_, layers_.size() + 1);
  layers_.emplace_back();
  layers_.back().first_vertex = vertices_taken_;
  return Status::ok;
}

std::size_t EdgeSmoothing::layer_of(std::uint64_t index, std::size_t near) const {
  const std::size_t from = near > 0 ? near - 1 : 0;
  const std::size_t to = std::min(near + 1, layers_.size() - 1);
  for (std::size_t l = from; l <= to; ++l) {
    const Layer& layer = layers_[l];
    if (index >= layer.first_vertex && index < layer.first_vertex + layer.vertices.size()) return l;
  }
  return layers_.size();  // not held: the engine's polygons never reach further
}

void EdgeSmoothing::advance(std::size_t layer_index) {
  Layer& layer = layers_[layer_index];
  const std::size_t count = layer.vertices.size();
  // The positions its polygons can reach, at the iteration it advances from, side by side: the
  // layer below (which has gone one iteration further already, so its previous one), its own
  // and the layer above. A corner is then one subtraction away.
  const std::size_t below = layer_index > 0 ? layer_index - 1 : layer_index;
  const std::size_t above = std::min(layer_index + 1, layers_.size() - 1);
  const std::uint64_t base = layers_[below].first_vertex;
  const std::uint64_t end = layers_[above].first_vertex + layers_[above].vertices.size();
  around_.resize(3 * static_cast<std::size_t>(end - base));
  for (std::size_t l = below; l <= above; ++l) {
    const Layer& held = layers_[l];
    const std::vector<float>& coordinate = l + 1 == layer_index ? held.previous : held.current;
    double* out = &around_[3 * static_cast<std::size_t>(held.first_vertex - base)];
    for (std::size_t i = 0; i < held.vertices.size(); ++i, out += 3) {
      const Vertex& vertex = held.vertices[i];
      out[0] = vertex.x;
      out[1] = vertex.y;
      out[2] = vertex.z;
      out[axis_of(vertex)] = coordinate[i];
    }
  }
  sums_.assign(3 * count, 0.0);
  normals_.assign(3 * count, 0.0);
  counts_.assign(count, 0);
  const std::uint64_t own_from = layer.first_vertex - base;
  // The polygons around the layer's vertices: its own cube layer and the one above.
  for (std::size_t q = layer_index; q <= above; ++q) {
    const Layer& holder = layers_[q];
    const std::uint64_t taken = holder.first_vertex + holder.vertices.size();
    for (const Polygon& polygon : holder.polygons) {
      const int n = polygon.vertex_count;
      std::uint64_t at[kMaxPolygonVertices];
      const double* p[kMaxPolygonVertices];
      bool reachable = true;
      for (int k = 0; k < n; ++k) {
        at[k] = whole_vertex_index(polygon.vertices[k], taken) - base;
        reachable = reachable && at[k] < end - base;
        p[k] = reachable ? &around_[3 * static_cast<std::size_t>(at[k])] : nullptr;
      }
      if (!reachable) continue;  // the engine's polygons never reach further than a layer
      // The polygon's vector area (Newell): its normal times its area.
      double area[3] = {0, 0, 0};
      for (int k = 0; k < n; ++k) {
        const double* a = p[k];
        const double* b = p[k + 1 < n ? k + 1 : 0];
        area[0] += 0.5 * (a[1] * b[2] - a[2] * b[1]);
        area[1] += 0.5 * (a[2] * b[0] - a[0] * b[2]);
        area[2] += 0.5 * (a[0] * b[1] - a[1] * b[0]);
      }
      for (int k = 0; k < n; ++k) {
        if (at[k] < own_from || at[k] >= own_from + count) continue;
        const std::size_t i = static_cast<std::size_t>(at[k] - own_from);
        const double* before = p[k > 0 ? k - 1 : n - 1];
        const double* after = p[k + 1 < n ? k + 1 : 0];
        for (int d = 0; d < 3; ++d) {
          sums_[3 * i + d] += before[d] + after[d];
          normals_[3 * i + d] += area[d];
        }
        counts_[i] += 2;
      }
    }
  }
  next_.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vertex& vertex = layer.vertices[i];
    const int axis = axis_of(vertex);
    const float lower = lower_end(vertex);
    next_[i] = layer.current[i];
    if (lower < 0.0f || lower + 1.0f >= static_cast<float>(size_[axis]) || counts_[i] == 0)
      continue;  // on the volume's border, where the surface closes: it stays
    const double* n = &normals_[3 * i];
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 0.0)) continue;
    double p[3] = {vertex.x, vertex.y, vertex.z};
    p[axis] = layer.current[i];
    double across = 0.0;  // n.(mean - p)
    for (int d = 0; d < 3; ++d) across += n[d] / length * (sums_[3 * i + d] / counts_[i] - p[d]);
    double axis_normal = n[axis] / length;
    if (std::fabs(axis_normal) < kMinAxisNormal)
      axis_normal = std::copysign(kMinAxisNormal, axis_normal);
    const double moved = p[axis] + kStep * across / axis_normal;
    next_[i] = static_cast<float>(
        std::clamp(moved, double{lower + kMargin}, double{lower + 1.0f - kMargin}));
  }
  layer.previous.swap(layer.current);
  layer.current.assign(next_.begin(), next_.end());
}

Status EdgeSmoothing::send(std::size_t layer_index) {
  const Layer& layer = layers_[layer_index];
  const std::size_t count = layer.vertices.size();
  for (std::size_t first = 0; first < count; first += kBatch) {
    const std::size_t end = std::min(count, first + kBatch);
    out_vertices_.assign(layer.vertices.begin() + first, layer.vertices.begin() + end);
    for (std::size_t i = first; i < end; ++i) {
      along_axis(out_vertices_[i - first]) = layer.current[i];
    }
    if (const Status status = downstream_.consume_vertices(out_vertices_.data(), end - first);
        status != Status::ok)
      return status;
  }
  const std::uint64_t taken = layer.first_vertex + count;
  for (std::size_t first = 0; first < layer.polygons.size(); first += kBatch) {
    const std::size_t end = std::min(layer.polygons.size(), first + kBatch);
    if (const Status status = downstream_.consume_polygons(&layer.polygons[first], end - first);
        status != Status::ok)
      return status;
    if (!send_geometry_) continue;
    out_geometry_.resize(end - first);
    for (std::size_t p = first; p < end; ++p) {
      const Polygon& polygon = layer.polygons[p];
      PolygonGeometry& by_value = out_geometry_[p - first];
      by_value.vertex_count = polygon.vertex_count;
      for (int k = 0; k < polygon.vertex_count; ++k) {
        const std::uint64_t index = whole_vertex_index(polygon.vertices[k], taken);
        const Layer& holder = layers_[layer_of(index, layer_index)];
        const std::size_t i = static_cast<std::size_t>(index - holder.first_vertex);
        by_value.vertices[k] = holder.vertices[i];
        along_axis(by_value.vertices[k]) = holder.current[i];
      }
    }
    if (const Status status =
            downstream_.consume_polygon_geometry(out_geometry_.data(), end - first);
        status != Status::ok)
      return status;
  }
  return Status::ok;
}

}  // namespace mvox
