#include "write/mesh/mesh_arrays.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <utility>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MVOX_MESH_ARRAYS_AVX2 1
#else
#define MVOX_MESH_ARRAYS_AVX2 0
#endif

namespace mvox {

MeshArraysWriter::MeshArraysWriter(const MeshWriterOptions& options, std::string subject)
    : MeshWriter(options, Faces::as_polygons, Positions::not_needed),
      subject_(std::move(subject)) {}

void MeshArraysWriter::write_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  // Grown once a batch and filled through a pointer: an insert per vertex cost more than the
  // engine took to find it.
  const std::size_t first = arrays_.vertices.size();
  arrays_.vertices.resize(first + 3 * vertex_count);
  float* out = arrays_.vertices.data() + first;
  for (std::size_t i = 0; i < vertex_count; ++i, out += 3)
    for (int axis = 0; axis < 3; ++axis) out[axis] = vertices[i].position[axis];
  if (!options().writes_normals()) return;
  const std::size_t first_normal = arrays_.normals.size();
  arrays_.normals.resize(first_normal + 3 * vertex_count);
  float* normal = arrays_.normals.data() + first_normal;
  for (std::size_t i = 0; i < vertex_count; ++i, normal += 3)
    for (int axis = 0; axis < 3; ++axis) normal[axis] = vertices[i].normal[axis];
}

void MeshArraysWriter::write_faces(const Polygon* faces, std::size_t face_count,
                                   std::uint32_t index_offset) {
  // Past 2^31 vertices an index may not fit 32 signed bits: 64 from here on. A writer of
  // pieces (mvox.Extractor) starts each piece's arrays afresh, so the count decides, not them.
  if (vertices_written() > kNarrowIndexVertices) {
    if (!arrays_.wide) widen_indices(arrays_);
    append_wide_polygons(arrays_, faces, face_count, index_offset, vertices_written());
    return;
  }
  if (index_offset == 0) {
    append_polygons(arrays_, faces, face_count);
    return;
  }
  // Moved a run at a time (slab-parallel runs only; Python's arrays come from one engine).
  Polygon moved[256];
  for (std::size_t first = 0; first < face_count; first += std::size(moved)) {
    const std::size_t count = std::min(std::size(moved), face_count - first);
    for (std::size_t i = 0; i < count; ++i) {
      moved[i] = faces[first + i];
      for (int k = 0; k < moved[i].vertex_count; ++k) moved[i].vertices[k] += index_offset;
    }
    append_polygons(arrays_, moved, count);
  }
}

namespace {

static_assert(sizeof(Vertex) == 4 * sizeof(float) && offsetof(Vertex, x) == 0 &&
                  offsetof(Vertex, y) == sizeof(float) && offsetof(Vertex, z) == 2 * sizeof(float),
              "x, y, z lead a 16-byte Vertex");
static_assert(sizeof(Polygon::vertices[0]) == sizeof(std::int32_t), "indices are copied as bytes");

// Grows the indices by seven a polygon (the most it can have; the caller cuts them back to
// what it wrote) and the offsets by one a polygon. Returns where the first of each goes.
template <class Index>
std::pair<Index*, std::int64_t*> room_for_polygons(ArrayOf<Index>& indices,
                                                   ArrayOf<std::int64_t>& offsets,
                                                   std::size_t count) {
  const std::size_t first_index = indices.size();
  const std::size_t first_face = offsets.size();
  indices.resize(first_index + count * kMaxPolygonVertices);
  offsets.resize(first_face + count);
  return {indices.data() + first_index, offsets.data() + first_face};
}

#if MVOX_MESH_ARRAYS_AVX2
static_assert(sizeof(Polygon) == 32 && offsetof(Polygon, vertices) == 4 && kMaxPolygonVertices == 7,
              "a polygon is its count in 4 bytes, then seven 32-bit indices: one AVX2 load");

// Numbers written in order to `dest` through a small staging buffer, whence whole 32-byte blocks
// go out with non-temporal stores: a mesh's arrays are megabytes that are not read again here,
// and an ordinary store must first read the line it writes into the cache. The staging buffer
// sits at the same place in a block as `dest`, so that its blocks are the destination's.
// Callers write up to 32 bytes at slot() (past what they keep), then advance() by what they
// keep; finish() writes the rest with ordinary stores and orders the non-temporal ones.
// `dest` must be aligned to sizeof(T), as every GrowableArray's elements are (malloc's 16
// bytes, or a mapping's page), so that the stage's blocks fall on the destination's.
template <class T>
class StagedStream {
  static constexpr std::size_t kBlock = 32 / sizeof(T);    // numbers in a 32-byte block
  static constexpr std::size_t kStage = 4096 / sizeof(T);  // flushed beyond this many

 public:
  explicit StagedStream(T* dest)
      : dest_(dest), lead_(reinterpret_cast<std::uintptr_t>(dest) % 32 / sizeof(T)), fill_(lead_) {}

  T* slot() { return stage_ + fill_; }
  __attribute__((target("avx2"))) void advance(std::size_t count) {
    fill_ += count;
    if (fill_ >= kStage) flush_blocks();
  }
  __attribute__((target("avx2"))) void finish() {
    const std::size_t from = flushed_ == 0 ? lead_ : 0;
    std::memcpy(dest_ + flushed_ + from - lead_, stage_ + from, (fill_ - from) * sizeof(T));
    _mm_sfence();
  }

 private:
  // Stage position p, counted from the start of the block `dest_` is in, goes to
  // dest_[flushed_ + p - lead_].
  __attribute__((target("avx2"))) void flush_blocks() {
    const std::size_t whole = fill_ / kBlock * kBlock;
    std::size_t k = 0;
    if (flushed_ == 0) {  // the first block starts before `dest_`: only its part from lead_ on
      std::memcpy(dest_, stage_ + lead_, (kBlock - lead_) * sizeof(T));
      k = kBlock;
    }
    for (; k < whole; k += kBlock)
      _mm256_stream_si256(reinterpret_cast<__m256i*>(dest_ + flushed_ + k - lead_),
                          _mm256_load_si256(reinterpret_cast<const __m256i*>(stage_ + k)));
    flushed_ += whole;
    std::memcpy(stage_, stage_ + whole, (fill_ - whole) * sizeof(T));
    fill_ -= whole;
  }

  T* dest_;
  std::size_t lead_;
  std::size_t fill_;         // stage positions written
  std::size_t flushed_ = 0;  // stage positions gone out before stage_[0]
  alignas(32) T stage_[kStage + 2 * kBlock];
};

// A polygon's slots (lanes 1-7 of its 32 bytes, moved down to 0-6) in one 32-byte store, two
// vertices' six floats (lanes 0-2 and 4-6, moved to 0-5) in one, all staged and streamed.
// mvox.extract came 7.6% (engine) and 9.5% (MRbrain) faster so, against 16-byte ordinary
// stores (docs/benchmarks.md). Like the plain loop, it trusts each polygon's size to be 3 to
// 7: MeshWriter checks it, and mvox.extract's own sink takes the engine's.
__attribute__((target("avx2"))) void append_polygons_avx2(MeshArrays& arrays,
                                                          const Polygon* polygons,
                                                          std::size_t count) {
  if (count == 0) return;  // an array never grown has no memory to stream into
  const __m256i slots_down = _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 7);
  std::int64_t at = static_cast<std::int64_t>(arrays.polygon_indices.size());  // before the room
  const auto [first_index, first_offset] =
      room_for_polygons(arrays.polygon_indices, arrays.polygon_offsets, count);
  StagedStream<std::int32_t> indices(first_index);
  StagedStream<std::int64_t> offsets(first_offset);
  for (std::size_t i = 0; i < count; ++i) {
    __m256i lanes;
    std::memcpy(&lanes, &polygons[i], sizeof lanes);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(indices.slot()),
                        _mm256_permutevar8x32_epi32(lanes, slots_down));
    indices.advance(polygons[i].vertex_count);
    at += polygons[i].vertex_count;
    *offsets.slot() = at;
    offsets.advance(1);
  }
  indices.finish();
  offsets.finish();
  arrays.polygon_indices.resize(static_cast<std::size_t>(at));
}

__attribute__((target("avx2"))) void append_vertex_positions_avx2(MeshArrays& arrays,
                                                                  const Vertex* vertices,
                                                                  std::size_t count) {
  if (count == 0) return;
  const __m256i positions_down = _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 7, 7);
  const std::size_t first = arrays.vertices.size();
  arrays.vertices.resize(first + 3 * count);
  StagedStream<float> positions(arrays.vertices.data() + first);
  std::size_t i = 0;
  for (; i + 2 <= count; i += 2) {
    __m256i pair;
    std::memcpy(&pair, &vertices[i], sizeof pair);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(positions.slot()),
                        _mm256_permutevar8x32_epi32(pair, positions_down));
    positions.advance(6);
  }
  if (i < count) {
    std::memcpy(positions.slot(), &vertices[i], sizeof(Vertex));
    positions.advance(3);
  }
  positions.finish();
}
#endif

// Asked once, on the first call (not while statics are built: the CPU model may not be read
// yet then).
bool has_avx2() {
#if MVOX_MESH_ARRAYS_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
#else
  return false;
#endif
}

}  // namespace

void append_polygons_portable(MeshArrays& arrays, const Polygon* polygons, std::size_t count) {
  std::int64_t at = static_cast<std::int64_t>(arrays.polygon_indices.size());  // before the room
  auto [index, offset] = room_for_polygons(arrays.polygon_indices, arrays.polygon_offsets, count);
  for (std::size_t i = 0; i < count; ++i) {
    const Polygon& polygon = polygons[i];
    std::memcpy(index, polygon.vertices, sizeof polygon.vertices);  // < 2^31 (narrow): whole
    index += polygon.vertex_count;
    at += polygon.vertex_count;
    *offset++ = at;
  }
  arrays.polygon_indices.resize(static_cast<std::size_t>(at));
}

void append_vertex_positions_portable(MeshArrays& arrays, const Vertex* vertices,
                                      std::size_t count) {
  const std::size_t first = arrays.vertices.size();
  arrays.vertices.resize(first + 3 * count + 1);  // the last vertex's fourth float
  float* out = arrays.vertices.data() + first;
  for (std::size_t i = 0; i < count; ++i, out += 3) std::memcpy(out, &vertices[i], sizeof(Vertex));
  arrays.vertices.resize(first + 3 * count);
}

void widen_indices(MeshArrays& arrays) {
  if (arrays.wide) return;
  const std::size_t count = arrays.polygon_indices.size();
  arrays.wide_polygon_indices.resize(arrays.wide_polygon_indices.size() + count);
  std::int64_t* wide =
      arrays.wide_polygon_indices.data() + arrays.wide_polygon_indices.size() - count;
  const std::int32_t* narrow = arrays.polygon_indices.data();
  for (std::size_t i = 0; i < count; ++i) wide[i] = narrow[i];
  arrays.polygon_indices = ArrayOf<std::int32_t>();
  arrays.wide = true;
}

void append_wide_polygons(MeshArrays& arrays, const Polygon* polygons, std::size_t count,
                          std::uint32_t index_offset, std::uint64_t vertices_taken) {
  auto [index, offset] =
      room_for_polygons(arrays.wide_polygon_indices, arrays.polygon_offsets, count);
  for (std::size_t i = 0; i < count; ++i) {
    const Polygon& polygon = polygons[i];
    for (int k = 0; k < polygon.vertex_count; ++k)
      *index++ = static_cast<std::int64_t>(
          whole_vertex_index(polygon.vertices[k] + index_offset, vertices_taken));
    *offset++ = index - arrays.wide_polygon_indices.data();
  }
  arrays.wide_polygon_indices.resize(
      static_cast<std::size_t>(index - arrays.wide_polygon_indices.data()));
}

void append_polygons(MeshArrays& arrays, const Polygon* polygons, std::size_t count) {
#if MVOX_MESH_ARRAYS_AVX2
  if (has_avx2()) return append_polygons_avx2(arrays, polygons, count);
#endif
  append_polygons_portable(arrays, polygons, count);
}

void append_vertex_positions(MeshArrays& arrays, const Vertex* vertices, std::size_t count) {
#if MVOX_MESH_ARRAYS_AVX2
  if (has_avx2()) return append_vertex_positions_avx2(arrays, vertices, count);
#endif
  append_vertex_positions_portable(arrays, vertices, count);
}

}  // namespace mvox
