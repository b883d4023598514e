#include "write/mesh/polygon_scan.h"

#include <algorithm>
#include <cstddef>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MVOX_POLYGON_SCAN_AVX2 1
#else
#define MVOX_POLYGON_SCAN_AVX2 0
#endif

namespace mvox {

PolygonScan scan_polygons_portable(const Polygon* polygons, std::size_t count) {
  PolygonScan scan;
  for (std::size_t i = 0; i < count; ++i) {
    const Polygon& polygon = polygons[i];
    const unsigned size = polygon.vertex_count;
    scan.sizes_ok &= size - 3u <= unsigned{kMaxPolygonVertices} - 3u;
    for (int k = 0; k < kMaxPolygonVertices; ++k)
      if (k < static_cast<int>(size)) scan.highest = std::max(scan.highest, polygon.vertices[k]);
  }
  return scan;
}

#if MVOX_POLYGON_SCAN_AVX2
namespace {

static_assert(sizeof(Polygon) == 32 && offsetof(Polygon, vertices) == 4 && kMaxPolygonVertices == 7,
              "a polygon is its count in 4 bytes, then seven 32-bit indices: one AVX2 load");

// A polygon as eight 32-bit lanes: lane 0 its count (and padding), lane k its slot k - 1. Lane
// k is a vertex when k <= count: compared against lane numbers whose lane 0 is larger than any
// count, so that lane 0 never is. The used lanes go into `highest` lane by lane, the largest of
// the eight taken at the end; whether any size is out of range is or-ed into `bad_size`.
__attribute__((target("avx2"))) PolygonScan scan_polygons_avx2(const Polygon* polygons,
                                                               std::size_t count) {
  const __m256i lane_numbers = _mm256_setr_epi32(0x7fffffff, 1, 2, 3, 4, 5, 6, 7);
  __m256i highest = _mm256_setzero_si256();
  unsigned bad_size = 0;
  for (std::size_t i = 0; i < count; ++i) {
    __m256i lanes;
    std::memcpy(&lanes, &polygons[i], sizeof lanes);
    const unsigned size = polygons[i].vertex_count;
    bad_size |= static_cast<unsigned>(size - 3u > unsigned{kMaxPolygonVertices} - 3u);
    const __m256i used =
        _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(size) + 1), lane_numbers);
    highest = _mm256_max_epu32(highest, _mm256_and_si256(lanes, used));
  }
  // The largest of the eight lanes.
  __m128i half =
      _mm_max_epu32(_mm256_castsi256_si128(highest), _mm256_extracti128_si256(highest, 1));
  half = _mm_max_epu32(half, _mm_shuffle_epi32(half, _MM_SHUFFLE(1, 0, 3, 2)));
  half = _mm_max_epu32(half, _mm_shuffle_epi32(half, _MM_SHUFFLE(2, 3, 0, 1)));
  PolygonScan scan;
  scan.sizes_ok = bad_size == 0;
  scan.highest = static_cast<std::uint32_t>(_mm_cvtsi128_si32(half));
  return scan;
}

}  // namespace
#endif

PolygonScan scan_polygons(const Polygon* polygons, std::size_t count) {
#if MVOX_POLYGON_SCAN_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return scan_polygons_avx2(polygons, count);
#endif
  return scan_polygons_portable(polygons, count);
}

}  // namespace mvox
