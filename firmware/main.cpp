// The mvox firmware demo: the core (firmware_like/) as firmware on a Cortex-M7 board, and the
// same program on the host. A 3-D Shepp-Logan head phantom from sim/ is evaluated slice by slice
// into a static buffer, streamed through the engine into a sink that only counts and checksums,
// and the results are printed. scripts/firmware_demo.sh builds it for both, runs it on the host
// and in QEMU, and requires the same results from both.
//
// All memory is static: the engine's workspace and the slice buffer are arrays of fixed size,
// the rest lives on the stack; the allocator traps (traps.cpp).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "checksum_sink.h"
#include "mvox/assert.h"
#include "mvox/engine.h"
#include "mvox/status.h"
#include "mvox/stream_volume.h"
#include "phantom_slices.h"
#include "platform.h"
#include "shepp_logan.h"

namespace mvox::firmware {
namespace {

// The volume: 64 slices of 64x64 voxels, the phantom `mvox demo --size 64` scans.
constexpr std::uint32_t kSide = 64;
// The surface: density >= 0.25 (sim::default_density_threshold("shepp-logan")).
constexpr double kDensityThreshold = 0.25;
// Batches of 256 vertices and polygons keep the workspace near 15 KB; the default 4096 would
// add about 190 KB. The output is the same whatever the batch size.
constexpr std::uint32_t kBatch = 256;
// The workspace's size is fixed at build time; main() checks engine_workspace_bytes() against
// it and halts when it is short.
constexpr std::size_t kWorkspaceBytes = 16 * 1024;

alignas(kWorkspaceAlignment) unsigned char g_workspace[kWorkspaceBytes];
std::uint8_t g_slice[kSide * kSide];

void print_line(const char* label, std::uint64_t value) {
  console_write(label);
  console_write_decimal(value);
  console_write("\n");
}

void check(Status status, const char* what) {
  if (status == Status::ok) return;
  console_write(what);
  console_write(": ");
  console_write(status_message(status));
  console_write("\n");
  halt("the engine refused");
}

#if defined(FIRMWARE_DEMO_ALLOCATE)
// The negative control the demo's script builds: one allocation, which must halt the program.
void* volatile g_allocated;
void allocate_on_purpose() {
  console_write("allocating on purpose (negative control)\n");
  g_allocated = ::operator new(16);
}
#endif

int run() {
  set_assert_handler(halt_on_assert);
#if defined(FIRMWARE_DEMO_ALLOCATE)
  allocate_on_purpose();
#endif
  const sim::SheppLogan3D phantom({kSide, kSide, kSide});
  PhantomSlices source(phantom, g_slice, sizeof g_slice);
  if (!source.fits()) halt("the slice buffer is too small for the phantom's slices");
  // sim::sample_threshold(): the density threshold in samples, rounded up.
  const double threshold = std::ceil(255.0 * kDensityThreshold);

  EngineOptions options;
  options.vertices_per_batch = kBatch;
  options.polygons_per_batch = kBatch;
  const std::size_t needed = engine_workspace_bytes(kSide, kSide, options);
  console_write("target: engine workspace ");
  console_write_decimal(needed);
  console_write(" bytes of ");
  console_write_decimal(sizeof g_workspace);
  console_write(" static, for 64x64 slices and batches of 256 (default batches: ");
  console_write_decimal(engine_workspace_bytes(kSide, kSide, EngineOptions{}));
  console_write(")\n");
  if (needed == 0 || needed > sizeof g_workspace) halt("the static workspace is too small");

  console_write("phantom: shepp-logan 64x64x64, u8 samples (partial volume), sample threshold ");
  console_write_decimal(static_cast<std::uint64_t>(threshold));
  console_write("\n");

  ChecksumSink sink;
  Engine engine;
  check(engine.init(g_workspace, sizeof g_workspace, kSide, kSide, threshold, options, &sink),
        "Engine::init");
  check(stream_volume(source, engine), "stream_volume");

  const EngineCounters& counters = engine.counters();
  print_line("slices: ", counters.slices);
  print_line("inner voxels: ", counters.inner_voxels);
  print_line("vertices: ", sink.vertices());
  console_write("polygons: ");
  console_write_decimal(sink.polygons());
  for (int n = 3; n <= kMaxPolygonVertices; ++n) {
    console_write(n == 3 ? " (" : ", ");
    console_write_decimal(sink.polygons_of_size(n));
    console_write(" of ");
    console_write_decimal(static_cast<std::uint64_t>(n));
  }
  console_write(" vertices)\n");
  console_write("vertex checksum: ");
  console_write_hex64(sink.vertex_checksum());
  console_write(" (FNV-1a 64)\npolygon checksum: ");
  console_write_hex64(sink.polygon_checksum());
  console_write(" (FNV-1a 64)\n");
  print_line("broken polygons: ", sink.broken_polygons());

  // The sink's counts must agree with the engine's own.
  const bool consistent = counters.vertices == sink.vertices() &&
                          counters.polygons == sink.polygons() && sink.broken_polygons() == 0 &&
                          counters.slices == kSide;
  print_target_lines();
  console_write(consistent ? "result: ok\n" : "result: INCONSISTENT\n");
  return consistent ? 0 : 1;
}

}  // namespace
}  // namespace mvox::firmware

int main() { return mvox::firmware::run(); }
