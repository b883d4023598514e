// mvox extract --labels: one closed surface per label of a label map, each the surface one
// engine extracts from that label's own mask (the same PLY data, byte for byte), touching labels
// each closed, a label that leaves the slices and comes back one mesh; the choices of labels,
// the refusals, a failure that leaves nothing; and a real segmentation made from CThead and
// written as NIfTI.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "mesh_topology.h"
#include "nifti_files.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "volume_files.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;

constexpr int kSize = 40;

// Label 1: a ball; label 2: a ball touching it (their voxels meet face to face); label 3: two
// rods along z with a gap between them (the label leaves the slices and comes back); label 7:
// one voxel.
std::vector<std::uint8_t> label_map() {
  std::vector<std::uint8_t> v(kSize * kSize * kSize, 0);
  for (int z = 0; z < kSize; ++z)
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        std::uint8_t& label = v[(z * kSize + y) * kSize + x];
        const int dy = y - 20, dz = z - 20;
        if ((x - 12) * (x - 12) + dy * dy + dz * dz < 64) label = 1;
        if (x >= 20 && (x - 28) * (x - 28) + dy * dy + dz * dz < 64) label = 2;
        if ((x - 20) * (x - 20) + (y - 5) * (y - 5) < 5 && ((z > 3 && z < 12) || (z > 20 && z < 33)))
          label = 3;
      }
  v[(35 * kSize + 35) * kSize + 35] = 7;
  return v;
}

std::vector<unsigned char> bytes_of(const std::vector<std::uint8_t>& v) {
  return std::vector<unsigned char>(v.begin(), v.end());
}

const char* kRaw = "--raw 40x40x40:u8";

TEST(LabelsCli, EachLabelIsTheSurfaceOfItsOwnMaskAndClosed) {
  ScratchDirectory dir;
  const std::vector<std::uint8_t> labels = label_map();
  test::volume_files::write_file(dir / "labels.raw", "", bytes_of(labels));
  const test::CommandResult run = run_mvox(
      std::string("extract labels.raw ") + kRaw + " --labels -o 'organ_{label}.ply' --stats s.json -q",
      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const int label : {1, 2, 3, 7}) {
    SCOPED_TRACE("label " + std::to_string(label));
    std::vector<std::uint8_t> mask(labels.size());
    for (std::size_t i = 0; i < labels.size(); ++i) mask[i] = labels[i] == label;
    test::volume_files::write_file(dir / "mask.raw", "", bytes_of(mask));
    ASSERT_EQ(run_mvox(std::string("extract mask.raw ") + kRaw + " -t 1 -o mask.ply -q", dir.path())
                  .exit_code,
              0);
    const std::string file = dir / ("organ_" + std::to_string(label) + ".ply");
    EXPECT_TRUE(test::ply_body(file) == test::ply_body(dir / "mask.ply"));
    const test::Topology topology = test::analyse(test::to_mesh(read_ply(file)));
    EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
    EXPECT_GT(topology.signed_volume, 0);
  }
  EXPECT_FALSE(fs::exists(dir / "organ_0.ply")) << "0 is the background";
  const std::string report = test::read_bytes(dir / "s.json");
  EXPECT_NE(report.find("\"label\": 3, \"vertices\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"engines\": 2, \"file\": \"organ_3.ply\""), std::string::npos)
      << "label 3 comes back after a gap: two engines, one mesh\n" << report;
}

TEST(LabelsCli, AListTakesOnlyItsLabelsInAnyFormat) {
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "labels.raw", "", bytes_of(label_map()));
  ASSERT_EQ(run_mvox(std::string("extract labels.raw ") + kRaw +
                         " --labels 2,7,9 -o 'part_{label}.stl' -q",
                     dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(fs::exists(dir / "part_2.stl"));
  EXPECT_TRUE(fs::exists(dir / "part_7.stl"));
  EXPECT_FALSE(fs::exists(dir / "part_1.stl"));
  EXPECT_FALSE(fs::exists(dir / "part_9.stl")) << "a label absent from the volume gets no file";
  ASSERT_EQ(run_mvox(std::string("extract labels.raw ") + kRaw +
                         " --labels 1 -o 'o_{label}.obj' --triangulate -q",
                     dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(fs::exists(dir / "o_1.obj"));
}

TEST(LabelsCli, OptionsThatDoNotFitAreUsageErrorsAndAFailureLeavesNothing) {
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "labels.raw", "", bytes_of(label_map()));
  const std::string job = std::string("extract labels.raw ") + kRaw + " --labels";
  const std::pair<std::string, std::string> refused[] = {
      {job + " -o 'a_{label}.ply' -t 1", "leave -t out"},
      {job + " -o all.ply", "give -o with {label} in the file name"},
      {job + " -o '{label}/a.ply'", "give -o with {label} in the file name"},
      {job + " 0,1 -o 'a_{label}.ply'", "'0' is not a label"},
      {job + " 1,,2 -o 'a_{label}.ply'", "'' is not a label"},
      {job + " -o 'a_{label}.ply' --image p.png", "--image: not with --labels"},
      {job + " -o 'a_{label}.ply' --smooth 5", "--smooth: not with --labels"},
      {job + " -o 'a_{label}.ply' --method cubes", "leave out --method cubes"},
  };
  const std::string before = dir.listing();
  for (const auto& [command, problem] : refused) {
    expect_one_line_error(run_mvox(command, dir.path()), problem, 2);
    EXPECT_EQ(dir.listing(), before) << command;
  }
  // Asking for labels that are not there fails, and writes nothing.
  expect_one_line_error(run_mvox(job + " 5,6 -o 'a_{label}.ply'", dir.path()),
                        "none of the labels asked for is in the volume");
  EXPECT_EQ(dir.listing(), before);
  // Without --labels, -t is still required.
  expect_one_line_error(run_mvox(std::string("extract labels.raw ") + kRaw + " -o a.ply", dir.path()),
                        "--threshold is required", 2);
  // A volume that ends early fails after labels have been extracted: no mesh appears.
  test::NiftiFile cut;
  cut.dim[1] = cut.dim[2] = cut.dim[3] = kSize;
  cut.samples = bytes_of(label_map());
  cut.samples.resize(cut.samples.size() * 3 / 4);
  cut.gzip = true;
  test::write_nifti(dir / "cut.nii.gz", cut);
  const std::string with_cut = dir.listing();
  expect_one_line_error(run_mvox("extract cut.nii.gz --labels -o 'c_{label}.ply'", dir.path()),
                        "cut.nii.gz");
  EXPECT_EQ(dir.listing(), with_cut) << "a mesh or the spool was left behind";
}

// The number in `report` after "\"KEY\": ".
std::uint64_t report_number(const std::string& report, const std::string& key) {
  const std::size_t at = report.find("\"" + key + "\": ");
  return at == std::string::npos ? 0 : std::stoull(report.substr(at + key.size() + 4));
}

TEST(LabelsCli, MemoryFollowsTheLabelsAtOnceNotTheLabelsInTheVolume) {
  // 600 labels, two slices each, one after the other: never more than two engines, and the
  // 600 files wait to be published holding no buffers (a writer kept its batches once: 65 MB).
  constexpr int kSide = 32, kDepth = 1200;
  std::vector<std::uint16_t> labels;
  for (int z = 0; z < kDepth; ++z)
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x)
        labels.push_back(x >= 4 && x < 28 && y >= 4 && y < 28 ? static_cast<std::uint16_t>(z / 2 + 1) : 0);
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "many.raw", "", test::sample_bytes_of(labels));
  fs::create_directories(dir / "out");
  const test::CommandResult run = run_mvox(
      "extract many.raw --raw 32x32x1200:u16le --labels -o 'out/m_{label}.stl' --stats s.json -q",
      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string report = test::read_bytes(dir / "s.json");
  EXPECT_EQ(report_number(report, "most_engines_at_once"), 2u) << report;
  EXPECT_TRUE(fs::exists(dir / "out/m_600.stl"));
  const std::uint64_t grown =
      report_number(report, "peak_bytes") - report_number(report, "start_bytes");
  EXPECT_LT(grown, std::uint64_t{12} << 20) << report;
}

// CThead (../shared/datasets) segmented into skin (600 <= value < 1200) and bone (>= 1200),
// written as a NIfTI label map with CThead's voxel size: bone's surface is the single-threshold
// surface at 1200, and skin's is the surface of its own mask, both closed. The middle 128x128
// of each slice, to keep the topology check short.
TEST(LabelsCli, ACtheadSegmentationGivesEachTissueItsClosedSurface) {
  const fs::path slices = fs::path(MVOX_SHARED_DATASETS) / "cthead";
  if (!fs::exists(slices / "CThead.1")) GTEST_SKIP() << slices << " is absent (CThead slices)";
  constexpr int kSide = 256, kW = 128, kH = 128, kD = 113, kFrom = 64;
  std::vector<std::uint16_t> values;
  for (int z = 0; z < kD; ++z) {
    std::ifstream in(slices / ("CThead." + std::to_string(z + 1)), std::ios::binary);
    std::vector<unsigned char> raw(2 * kSide * kSide);
    ASSERT_TRUE(in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size())));
    for (int y = kFrom; y < kFrom + kH; ++y)
      for (int x = kFrom; x < kFrom + kW; ++x) {
        const int i = y * kSide + x;
        values.push_back(static_cast<std::uint16_t>(raw[2 * i] << 8 | raw[2 * i + 1]));
      }
  }
  std::vector<std::uint8_t> labels(values.size()), skin(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    labels[i] = values[i] >= 1200 ? 2 : values[i] >= 600 ? 1 : 0;
    skin[i] = labels[i] == 1;
  }
  ScratchDirectory dir;
  test::NiftiFile nifti;
  nifti.dim[1] = kW;
  nifti.dim[2] = kH;
  nifti.dim[3] = kD;
  nifti.pixdim[3] = 2;
  nifti.samples = bytes_of(labels);
  test::write_nifti(dir / "cthead_labels.nii", nifti);
  test::volume_files::write_file(dir / "skin.raw", "", bytes_of(skin));
  test::volume_files::write_file(dir / "ct.raw", "", test::sample_bytes_of(values));
  const test::CommandResult run = run_mvox(
      "extract cthead_labels.nii --labels -o 'tissue_{label}.ply' --stats s.json -q", dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string size = "128x128x113";
  ASSERT_EQ(run_mvox("extract ct.raw --raw " + size + ":u16le -t 1200 --spacing 1,1,2 -o bone.ply -q",
                     dir.path())
                .exit_code,
            0);
  ASSERT_EQ(run_mvox("extract skin.raw --raw " + size + ":u8 -t 1 --spacing 1,1,2 -o skin.ply -q",
                     dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(test::ply_body(dir / "tissue_2.ply") == test::ply_body(dir / "bone.ply"));
  EXPECT_TRUE(test::ply_body(dir / "tissue_1.ply") == test::ply_body(dir / "skin.ply"));
  for (const char* file : {"tissue_1.ply", "tissue_2.ply"}) {
    const test::Topology topology = test::analyse(test::to_mesh(read_ply(dir / file)));
    EXPECT_TRUE(topology.closed_and_consistent()) << file << ": " << test::describe(topology);
    EXPECT_GT(topology.faces, 10000u) << file;
  }
}

}  // namespace
}  // namespace mvox
