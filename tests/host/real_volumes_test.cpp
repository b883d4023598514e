// The engine on real scans from ../shared/datasets (skipped, with the reason, when absent):
// literal and fast engines give identical output, the surface is closed and consistently wound,
// and every vertex sits at an inner/outer voxel pair.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"

namespace mvox {
namespace {

struct RealVolume {
  const char* name;
  const char* input;  // relative to the datasets folder
  const char* raw;    // "" for image stacks
  double threshold;
};

// The paper's three volumes, plus a little-endian signed 16-bit CT (VTK's headsq, bone at 1150).
const RealVolume kVolumes[] = {
    {"CThead", "/cthead/CThead.*", "256x256:u16be", 600},
    {"engine", "/engine/engine_256x256x128_uint8.raw", "256x256x128:u8", 100},
    {"MRbrain", "/mrbrain8bit/mrbrain-8bit*.png", "", 50},
    {"headsq", "/headsq/quarter.[0-9]*", "64x64:i16le", 1150},
};

// Names the volume in test output instead of its bytes.
void PrintTo(const RealVolume& volume, std::ostream* out) { *out << volume.name; }

class RealVolumes : public ::testing::TestWithParam<RealVolume> {};

std::unique_ptr<SliceSource> open(const RealVolume& volume) {
  std::optional<RawFormat> raw;
  if (*volume.raw) raw = parse_raw_format(volume.raw);
  return open_slice_source({std::string(MVOX_SHARED_DATASETS) + volume.input}, raw);
}

TEST_P(RealVolumes, LiteralEqualsFastAndTheSurfaceIsClosed) {
  const RealVolume& volume = GetParam();
  const std::string folder = std::filesystem::path(std::string(MVOX_SHARED_DATASETS) + volume.input)
                                 .parent_path()
                                 .string();
  if (!std::filesystem::exists(folder))
    GTEST_SKIP() << folder << " is absent (../shared/datasets is not beside the checkout)";

  auto source = open(volume);
  const test::Mesh fast = test::extract(*source, volume.threshold);
  EngineOptions literal;
  literal.kind = EngineKind::literal;
  source = open(volume);
  EXPECT_TRUE(test::meshes_identical(fast, test::extract(*source, volume.threshold, literal)));

  const test::Topology t = test::analyse(fast);
  EXPECT_TRUE(t.closed_and_consistent()) << volume.name << ": " << test::describe(t);
  EXPECT_GT(t.signed_volume, 0);
  EXPECT_GT(t.faces, 1000u);

  // The paper's Table 1 on the same scan: same vertices, but holes (docs/surface_rules.md).
  EngineOptions table1;
  table1.rule = SurfaceRule::paper_table1;
  source = open(volume);
  const test::Topology paper = test::analyse(test::extract(*source, volume.threshold, table1));
  EXPECT_EQ(paper.vertices, t.vertices);
  EXPECT_GT(paper.open_edges, 0u) << volume.name;

  // The vertex oracle on the classified volume.
  source = open(volume);
  const VolumeInfo& info = source->info();
  test::BinaryVolume inner(info.width, info.height, info.depth);
  SliceView slice;
  for (std::uint32_t z = 0; source->next_slice(&slice); ++z)
    for (std::uint32_t y = 0; y < info.height; ++y)
      for (std::uint32_t x = 0; x < info.width; ++x) {
        const char* row = static_cast<const char*>(slice.samples) + y * slice.row_stride_bytes;
        double value = 0;
        switch (slice.type) {
          case SampleType::u8: value = reinterpret_cast<const std::uint8_t*>(row)[x]; break;
          case SampleType::u16: value = reinterpret_cast<const std::uint16_t*>(row)[x]; break;
          case SampleType::i16: value = reinterpret_cast<const std::int16_t*>(row)[x]; break;
          case SampleType::f32: value = reinterpret_cast<const float*>(row)[x]; break;
        }
        inner.at(x, y, z) = value >= volume.threshold;
      }
  const std::vector<Vertex> expected = test::expected_vertices(inner);
  const std::vector<Vertex> actual = test::sorted_positions(fast);
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i)
    ASSERT_TRUE(test::same_position(actual[i], expected[i])) << "vertex " << i;
}

INSTANTIATE_TEST_SUITE_P(SharedDatasets, RealVolumes, ::testing::ValuesIn(kVolumes),
                         [](const ::testing::TestParamInfo<RealVolume>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace mvox
