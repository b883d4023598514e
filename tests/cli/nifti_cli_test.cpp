// NIfTI volumes through the command line: the same surface as the same samples read raw, placed
// in NIfTI's world (a mirroring sform keeps the surface closed and wound outward), and bad files
// failing with one line and no output.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "mesh_topology.h"
#include "nifti_files.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "volume_files.h"
#include "volume_samples.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::NiftiFile;
using test::run_mvox;
using test::ScratchDirectory;

constexpr std::uint32_t kW = 13, kH = 11, kD = 9;

NiftiFile phantom_nifti() {
  NiftiFile file;
  file.dim[1] = kW;
  file.dim[2] = kH;
  file.dim[3] = kD;
  file.samples = test::sample_bytes_of(test::phantom_samples<std::uint8_t>(kW, kH, kD));
  return file;
}

test::Topology topology_of(const std::string& path) {
  return test::analyse(test::to_mesh(read_ply(path)));
}

TEST(NiftiCli, ANiftiVolumeGivesTheSurfaceOfItsSamplesReadRaw) {
  ScratchDirectory dir;
  NiftiFile file = phantom_nifti();
  test::volume_files::write_file(dir / "raw.raw", "", file.samples);
  for (const char* name : {"v.nii", "v.nii.gz", "p.hdr"}) {
    SCOPED_TRACE(name);
    file.gzip = std::string(name).find(".gz") != std::string::npos;
    file.pair = std::string(name).find(".hdr") != std::string::npos;
    test::write_nifti(dir / name, file);
    ASSERT_EQ(run_mvox(std::string("extract ") + name + " -t 100 -o n.ply -q", dir.path()).exit_code, 0);
    ASSERT_EQ(run_mvox("extract raw.raw --raw 13x11x9:u8 -t 100 -o r.ply -q", dir.path()).exit_code, 0);
    const PlyMesh from_nifti = read_ply(dir / "n.ply"), from_raw = read_ply(dir / "r.ply");
    EXPECT_EQ(from_nifti.positions, from_raw.positions);
    EXPECT_EQ(from_nifti.face_offsets, from_raw.face_offsets);
    EXPECT_EQ(from_nifti.face_indices, from_raw.face_indices);
  }
}

TEST(NiftiCli, AMirroringSformKeepsTheSurfaceClosedAndWoundOutward) {
  ScratchDirectory dir;
  NiftiFile file = phantom_nifti();
  file.sform_code = 1;
  // x negated (RAS from an LPS-like grid), anisotropic voxels, an offset.
  const double srow[3][4] = {{-0.5, 0, 0, 40}, {0, 0.5, 0, -20}, {0, 0, 2, 7}};
  std::memcpy(file.srow, srow, sizeof srow);
  file.gzip = true;
  test::write_nifti(dir / "m.nii.gz", file);
  file.gzip = false;
  const test::CommandResult run = run_mvox("extract m.nii.gz -t 100 -o m.ply -q", dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const test::Topology mirrored = topology_of(dir / "m.ply");
  EXPECT_TRUE(mirrored.closed_and_consistent()) << test::describe(mirrored);
  EXPECT_GT(mirrored.signed_volume, 0) << "wound inward after the mirror";
  // The volume enclosed scales by the voxel's volume, 0.5 * 0.5 * 2.
  file.sform_code = 0;
  test::write_nifti(dir / "plain.nii", file);
  ASSERT_EQ(run_mvox("extract plain.nii -t 100 -o p.ply -q", dir.path()).exit_code, 0);
  EXPECT_NEAR(mirrored.signed_volume, 0.5 * topology_of(dir / "p.ply").signed_volume, 1e-3);
  // And it lies where the sform puts it: x from 40 - 0.5 * 12 to 40.
  const PlyMesh mesh = read_ply(dir / "m.ply");
  for (const auto& p : mesh.positions) {
    EXPECT_GE(p[0], 40 - 0.5f * 12 - 1e-4f);
    EXPECT_LE(p[0], 40 + 1e-4f);
  }
}

TEST(NiftiCli, BadNiftiFilesFailWithOneLineAndLeaveNothing) {
  ScratchDirectory dir;
  NiftiFile four = phantom_nifti();
  four.dim[0] = 4;
  four.dim[4] = 3;
  test::write_nifti(dir / "four.nii", four);
  NiftiFile cut = phantom_nifti();
  cut.samples.resize(cut.samples.size() / 2);
  test::write_nifti(dir / "cut.nii.gz", cut);
  NiftiFile rgb = phantom_nifti();
  rgb.datatype = 128;
  rgb.bitpix = 24;
  test::write_nifti(dir / "rgb.nii", rgb);
  const std::string inputs = dir.listing();
  for (const char* input : {"four.nii", "cut.nii.gz", "rgb.nii"}) {
    expect_one_line_error(
        run_mvox(std::string("extract ") + input + " -t 100 -o out.ply --image out.png", dir.path()),
        input);
    EXPECT_EQ(dir.listing(), inputs) << "an output or temporary was left behind";
  }
  expect_one_line_error(run_mvox("extract four.nii --raw 13x11x9:u8 -t 100 -o out.ply", dir.path()),
                        "--raw: four.nii is a NIfTI file with its own header", 2);
}

}  // namespace
}  // namespace mvox
