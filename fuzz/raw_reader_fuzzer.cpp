// Fuzzes the raw readers (src/read/raw/raw_volume_source.h, src/read/raw/raw_slices_source.h) and
// the engine behind them with an arbitrary file and a fuzzed --raw spec.
//
// Input: a spec, a newline, then the file's bytes. WxHxD:TYPE reads the bytes as one volume,
// WxH:TYPE as one to three slice files with these bytes. Sizes are bounded (64 KiB a slice,
// 1 MiB a volume) so that a run never allocates much. Properties: a file of the wrong size is
// refused with a one-line error naming it; one of the right size gives back exactly its bytes,
// in native order; and the engine, at a threshold inside the sample range, emits only polygons
// of 3 to 7 vertices already sent.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "error.h"
#include "fuzz_check.h"
#include "memory_file.h"
#include "pipeline/pipeline.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"

namespace {

constexpr std::size_t kMaxSliceBytes = std::size_t{1} << 16;
constexpr std::size_t kMaxVolumeBytes = std::size_t{1} << 20;

// Checks what the engine sends: vertices before the polygons that use them, 3 to 7 of them.
class CheckingSink final : public mvox::PolygonSink {
 public:
  mvox::Status consume_vertices(const mvox::Vertex*, std::size_t vertex_count) override {
    vertices_ += vertex_count;
    return mvox::Status::ok;
  }
  mvox::Status consume_polygons(const mvox::Polygon* polygons, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i) {
      MVOX_FUZZ_CHECK(
          polygons[i].vertex_count >= 3 && polygons[i].vertex_count <= mvox::kMaxPolygonVertices,
          std::to_string(polygons[i].vertex_count));
      for (int k = 0; k < polygons[i].vertex_count; ++k)
        MVOX_FUZZ_CHECK(polygons[i].vertices[k] < vertices_, "vertex index not yet sent");
    }
    return mvox::Status::ok;
  }

 private:
  std::uint64_t vertices_ = 0;
};

double threshold_inside(mvox::SampleType type) {
  switch (type) {
    case mvox::SampleType::u8: return 128;
    case mvox::SampleType::u16: return 32768;
    case mvox::SampleType::i16: return 0.5;
    case mvox::SampleType::f32: return 0.5;
  }
  return 1;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto* newline = static_cast<const std::uint8_t*>(std::memchr(data, '\n', size));
  if (newline == nullptr) return 0;
  const std::string spec(reinterpret_cast<const char*>(data), newline - data);
  std::optional<mvox::RawFormat> format;
  try {
    format = mvox::parse_raw_format(spec);
  } catch (const mvox::Error&) {
    return 0;  // raw_format_fuzzer's business
  }
  const std::size_t slice_bytes = format->slice_bytes();
  if (slice_bytes > kMaxSliceBytes || std::uint64_t{format->depth} * slice_bytes > kMaxVolumeBytes)
    return 0;

  const std::uint8_t* bytes = newline + 1;
  const std::size_t byte_count = size - static_cast<std::size_t>(bytes - data);
  const std::string& path = mvox::fuzz::memory_file_with(bytes, byte_count);
  // One volume file, or the same file as 1 to 3 slices (the count from the file's size).
  const std::size_t files = format->depth > 0 ? 1 : 1 + byte_count % 3;
  const std::vector<std::string> inputs(files, path);
  const std::uint64_t slices = format->depth > 0 ? format->depth : files;
  const bool right_size = byte_count == (format->depth > 0 ? slices * slice_bytes : slice_bytes);

  std::unique_ptr<mvox::SliceSource> source;
  try {
    source = mvox::open_slice_source(inputs, format);
    std::vector<unsigned char> expected(slice_bytes);
    for (std::uint64_t k = 0; k < slices; ++k) {
      mvox::SliceView slice;
      MVOX_FUZZ_CHECK(source->next_slice(&slice), "a slice is missing");
      MVOX_FUZZ_CHECK(slice.width == format->width && slice.height == format->height &&
                          slice.type == format->type,
                      spec);
      const std::size_t offset = format->depth > 0 ? k * slice_bytes : 0;
      std::memcpy(expected.data(), bytes + offset, slice_bytes);
      mvox::swap_to_native(expected.data(), slice_bytes / format->bytes_per_sample,
                           format->bytes_per_sample, format->byte_order);
      for (std::uint32_t y = 0; y < slice.height; ++y)
        MVOX_FUZZ_CHECK(std::memcmp(static_cast<const unsigned char*>(slice.samples) +
                                        y * slice.row_stride_bytes,
                                    expected.data() + y * slice.width * format->bytes_per_sample,
                                    slice.width * format->bytes_per_sample) == 0,
                        "slice " + std::to_string(k) + " row " + std::to_string(y));
    }
    mvox::SliceView after;
    MVOX_FUZZ_CHECK(!source->next_slice(&after), "more slices than the spec says");
  } catch (const mvox::Error& e) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(e.what()), e.what());
    MVOX_FUZZ_CHECK(!right_size, std::string("refused a file of the right size: ") + e.what());
    MVOX_FUZZ_CHECK(e.subject() == path, e.what());
    return 0;
  }
  MVOX_FUZZ_CHECK(right_size, "read a file of the wrong size: " + spec);

  // The engine over the same samples, with a method chosen by the data.
  mvox::EngineOptions options;
  const std::uint8_t choice = byte_count > 0 ? bytes[0] : 0;
  if (choice & 1)
    options.method = mvox::SurfaceMethod::cubes;
  else if (choice & 2)
    options.kind = mvox::EngineKind::literal;
  if (!(choice & 1) && (choice & 4)) options.rule = mvox::SurfaceRule::paper_table1;
  source = mvox::open_slice_source(inputs, format);
  CheckingSink sink;
  const mvox::PipelineResult result =
      mvox::run_pipeline(*source, threshold_inside(format->type), options, sink, spec);
  MVOX_FUZZ_CHECK(result.status == mvox::Status::ok, mvox::status_message(result.status));
  MVOX_FUZZ_CHECK(result.counters.slices == slices, spec);
  return 0;
}
