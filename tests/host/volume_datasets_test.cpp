// The shared datasets tooth.nrrd and HeadMRVolume.mhd, when ../shared/datasets is present (never
// in the repository): size, type, spacing, origin, axes and mean sample as their INFO.txt gives
// them, and a closed, outward mesh through the command line that the spacing reaches.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "mesh_topology.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "volume_files.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::run_mvox;
using test::ScratchDirectory;
using test::volume_files::read_volume;

struct SharedVolume {
  const char* name;
  const char* file;  // relative to the datasets folder
  std::uint32_t width, height, depth;
  double spacing;
  double mean;  // from the dataset's INFO.txt
  double threshold;
};

void expect_shared_volume(const SharedVolume& volume) {
  const std::string path = std::string(MVOX_SHARED_DATASETS) + volume.file;
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (optional real data)";

  VolumeInfo info;
  const std::vector<std::uint8_t> samples = read_volume<std::uint8_t>(path, &info);
  EXPECT_EQ(info.width, volume.width);
  EXPECT_EQ(info.height, volume.height);
  EXPECT_EQ(info.depth, volume.depth);
  EXPECT_EQ(info.type, SampleType::u8);
  for (int a = 0; a < 3; ++a) {
    EXPECT_DOUBLE_EQ(info.spacing[a], volume.spacing);
    EXPECT_DOUBLE_EQ(info.origin[a], 0);
    for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(info.axes[a][i], a == i ? 1 : 0);
  }
  double sum = 0;
  for (std::uint8_t s : samples) sum += s;
  EXPECT_NEAR(sum / static_cast<double>(samples.size()), volume.mean, 0.001);

  ScratchDirectory dir;
  const test::CommandResult result =
      run_mvox("extract '" + path + "' -t " + std::to_string(volume.threshold) + " -o mesh.ply -q",
               dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const PlyMesh ply = read_ply(dir / "mesh.ply");
  const test::Topology t = test::analyse(test::to_mesh(ply));
  EXPECT_TRUE(t.closed_and_consistent()) << volume.name << ": " << test::describe(t);
  EXPECT_GT(t.signed_volume, 0);
  EXPECT_GT(t.faces, 1000u);
  // The spacing reaches the mesh: the largest coordinate is about (size - 1) * spacing.
  float max_x = 0;
  for (const auto& p : ply.positions) max_x = std::max(max_x, p[0]);
  EXPECT_LE(max_x, (volume.width - 0.5) * volume.spacing);
  EXPECT_GT(max_x, volume.width * volume.spacing / 2);
}

TEST(SharedDatasets, ToothNrrd) {
  expect_shared_volume({"tooth", "/tooth/tooth.nrrd", 103, 94, 161, 1, 103.165, 100});
}

TEST(SharedDatasets, HeadMrMetaImage) {
  expect_shared_volume(
      {"head_mr_small", "/head_mr_small/HeadMRVolume.mhd", 48, 62, 42, 4, 24.468, 50});
}

}  // namespace
}  // namespace mvox
