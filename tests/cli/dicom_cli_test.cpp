// DICOM series through the command line: a sphere series, axial and oblique, extracted to a
// closed mesh in patient coordinates; the series note, --series, one-line errors and --help; an
// unreadable entry beside the series named; placements beyond float refused; and the shared
// dataset's series extracted end to end (skipped, with the reason, when absent).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "command_runner.h"
#include "dicom_series.h"
#include "dicom_writer.h"
#include "mesh_capture.h"
#include "mesh_topology.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "shapes.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::DicomSliceSpec;
using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;
using test::dicom_series::dataset;
using test::dicom_series::Vec3;
using test::dicom_series::write_series;

// ---------------------------------------------------------------------------------------------
// The command line

bool position_less(const Vertex& a, const Vertex& b) {
  return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
}

// Writes a sphere phantom as a DICOM series with the given row and column cosines, extracts it
// through the command line, and checks the mesh: closed, outward, and every vertex in patient
// coordinates, origin + row * column spacing * x + column * row spacing * y + normal * gap * z.
void expect_sphere_series_in_patient_coordinates(const Vec3& row, const Vec3& column) {
  ScratchDirectory dir;
  fs::create_directory(dir / "scans");
  const sim::Grid grid{22, 19, 17};
  const sim::Sphere sphere(grid, sim::grid_centre(grid), 7.2);
  const Vec3 origin{-10, 20, 30};
  const Vec3 normal{row[1] * column[2] - row[2] * column[1],
                    row[2] * column[0] - row[0] * column[2],
                    row[0] * column[1] - row[1] * column[0]};
  const double gap = 1.5;
  DicomSliceSpec spec;
  spec.width = grid.width;
  spec.height = grid.height;
  spec.bits_stored = 12;
  spec.intercept = -1024;  // stored 24 is air (-1000 HU), 1100 is bone-like (76 HU)
  spec.pixel_spacing = std::array<double, 2>{0.6, 0.8};  // rows 0.6 apart, columns 0.8
  spec.orientation = std::array<double, 6>{row[0], row[1], row[2], column[0], column[1], column[2]};
  test::BinaryVolume inner(grid.width, grid.height, grid.depth);
  for (std::uint32_t z = 0; z < grid.depth; ++z) {
    spec.position = Vec3{origin[0] + normal[0] * z * gap, origin[1] + normal[1] * z * gap,
                         origin[2] + normal[2] * z * gap};
    spec.instance_number = grid.depth - z;  // numbered backwards, named shuffled
    spec.stored.clear();
    for (std::uint32_t y = 0; y < grid.height; ++y)
      for (std::uint32_t x = 0; x < grid.width; ++x) {
        const bool in = sphere.density(x, y, z) > 0.5f;
        inner.at(x, y, z) = in;
        spec.stored.push_back(in ? 1100 : 24);
      }
    test::write_dicom(dir / ("scans/IM" + std::to_string((z * 7) % grid.depth) + ".dcm"), spec);
  }

  const auto result = run_mvox("extract scans -t 0 -o sphere.ply -q", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "");  // quiet: not even the PixelSpacing or series notes
  const test::Mesh mesh = test::to_mesh(read_ply(dir / "sphere.ply"));
  const test::Topology topology = test::analyse(mesh);
  EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  EXPECT_EQ(topology.euler(), 2);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_GT(topology.signed_volume, 0);  // outward in patient space too

  std::vector<Vertex> expected = test::expected_vertices(inner);
  const double spacing[3] = {0.8, 0.6, gap};
  const Vec3 axes[3] = {row, column, normal};
  for (Vertex& v : expected) {
    const double voxel[3] = {v.x, v.y, v.z};
    double world[3] = {origin[0], origin[1], origin[2]};
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) world[k] += axes[a][k] * spacing[a] * voxel[a];
    v.x = static_cast<float>(world[0]);
    v.y = static_cast<float>(world[1]);
    v.z = static_cast<float>(world[2]);
  }
  std::vector<Vertex> actual = mesh.vertices;
  std::sort(expected.begin(), expected.end(), position_less);
  std::sort(actual.begin(), actual.end(), position_less);
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) {
    ASSERT_NEAR(actual[i].x, expected[i].x, 1e-4) << i;
    ASSERT_NEAR(actual[i].y, expected[i].y, 1e-4) << i;
    ASSERT_NEAR(actual[i].z, expected[i].z, 1e-4) << i;
  }
}

TEST(DicomCli, AxialSphereSeriesGivesAClosedSphereWhereTheHeaderPutsIt) {
  expect_sphere_series_in_patient_coordinates({1, 0, 0}, {0, 1, 0});
}

TEST(DicomCli, ObliqueSphereSeriesIsPlacedAlongItsOrientationInPatientCoordinates) {
  // Rows turned 30 degrees about z, then the plane tipped 20 degrees about the row direction.
  const double a = 30 * M_PI / 180, b = 20 * M_PI / 180;
  const Vec3 row{std::cos(a), std::sin(a), 0};
  const Vec3 column{-std::sin(a) * std::cos(b), std::cos(a) * std::cos(b), std::sin(b)};
  expect_sphere_series_in_patient_coordinates(row, column);
}

TEST(DicomCli, SeriesNotesErrorsAndHelp) {
  ScratchDirectory dir;
  fs::create_directory(dir / "scans");
  DicomSliceSpec a, b;
  a.series_uid = "1.2.826.0.1.3680043.10.543.21";
  b.series_uid = "1.2.826.0.1.3680043.10.543.22";
  a.pixel_spacing = b.pixel_spacing = std::array<double, 2>{1, 1};
  write_series((dir / "scans"), "a", a, 3, {0, 0, 0}, 1);
  write_series((dir / "scans"), "b", b, 2, {0, 0, 0}, 1);

  // Not quiet: one note line about the series, then the summary.
  auto noted = run_mvox("extract scans -t 100 -o a.ply", dir.path());
  ASSERT_EQ(noted.exit_code, 0) << noted.output;
  EXPECT_EQ(noted.output.rfind("mvox: note: scans: 2 DICOM series; reading the largest, " +
                                   a.series_uid + " (3 slices); also " + b.series_uid +
                                   " (2 slices); choose one with --series UID\n",
                               0),
            0u)
      << noted.output;
  auto picked = run_mvox("extract scans -t 100 -o b.ply -q --stats b.json --series " + b.series_uid,
                         dir.path());
  ASSERT_EQ(picked.exit_code, 0) << picked.output;
  std::ifstream stats(dir / "b.json");
  const std::string json((std::istreambuf_iterator<char>(stats)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"dimensions\": [16, 12, 2]"), std::string::npos) << json;

  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply --series 9.9", dir.path()),
                        "--series: no series 9.9 in scans; it holds " + a.series_uid);
  // Two slices in one place: refused before any output appears.
  DicomSliceSpec twin = a;
  twin.position = Vec3{0, 0, 1};
  test::write_dicom(dir / "scans/a9.dcm", twin);
  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply", dir.path()), "scans/a9.dcm");
  // A threshold beyond the 16-bit unsigned samples is refused as for any input.
  fs::remove(dir / "scans/a9.dcm");
  expect_one_line_error(run_mvox("extract scans -t 70000 -o x.ply", dir.path()), "scans");
  EXPECT_EQ(dir.listing(), "a.ply b.json b.ply scans ");

  const auto help = run_mvox("extract --help", dir.path());
  EXPECT_NE(help.output.find("DICOM"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--series"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--dicom"), std::string::npos) << help.output;
}

// An entry of the series' folder that cannot be read is named, as in an image stack, rather
// than hiding the series (the folder was then read as images and said to hold none).
TEST(DicomCli, AFifoOrADanglingLinkBesideTheSeriesIsNamed) {
  ScratchDirectory dir;
  fs::create_directory(dir / "scans");
  DicomSliceSpec spec;
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  write_series((dir / "scans"), "a", spec, 3, {0, 0, 0}, 1);
  ASSERT_EQ(::mkfifo((dir / "scans/pipe").c_str(), 0600), 0);
  // Never opened: with no writer, opening the FIFO would wait forever.
  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply", dir.path()),
                        "mvox: error: scans/pipe: is not a regular file (a FIFO, socket or "
                        "device), not a slice");
  fs::remove(dir / "scans/pipe");
  fs::create_symlink("gone.dcm", dir / "scans/a7.dcm");
  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply", dir.path()),
                        "mvox: error: scans/a7.dcm: is a dangling symbolic link");
  expect_one_line_error(run_mvox("extract 'scans/*' -t 100 -o x.ply", dir.path()),
                        "mvox: error: scans/a7.dcm: is a dangling symbolic link");
  EXPECT_EQ(dir.listing(), "scans ");
}

// A spacing or position that float coordinates cannot hold is refused naming the input, and
// called too large (not "must be positive and finite", as 1e300 is both).
TEST(DicomCli, SpacingOrPositionBeyondFloatIsRefusedNamingTheInput) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.pixel_spacing = std::array<double, 2>{1e300, 1};
  fs::create_directory(dir / "wide");
  write_series((dir / "wide"), "a", spec, 3, {0, 0, 0}, 1);
  expect_one_line_error(run_mvox("extract wide -t 100 -o x.ply", dir.path()),
                        "mvox: error: wide: spacing y is too large for float coordinates, got "
                        "1e+300 (usable: 2.35099e-38 to 3.40282e+38)");
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  fs::create_directory(dir / "far");
  write_series((dir / "far"), "a", spec, 3, {0, 1e300, 0}, 1);
  expect_one_line_error(run_mvox("extract far -t 100 --image x.png", dir.path()),
                        "mvox: error: far: origin y is too large for float coordinates, got "
                        "1e+300");
  // Slices 1e300 mm apart: the spacing along the normal.
  fs::create_directory(dir / "apart");
  write_series((dir / "apart"), "a", spec, 3, {0, 0, -1e300}, 1e300);
  expect_one_line_error(run_mvox("extract apart -t 100 -o x.ply", dir.path()),
                        "mvox: error: apart: spacing z is too large for float coordinates");
  EXPECT_EQ(dir.listing(), "apart far wide ");
}

// ---------------------------------------------------------------------------------------------
// Real files from ../shared/datasets

TEST(DicomDatasets, BbmriExtractedEndToEndIsAClosedSurface) {
  MVOX_REQUIRE_DATASET("dicom_mr_bbmri_6slices");
  ScratchDirectory dir;
  const auto result = run_mvox(
      "extract '" + dataset("dicom_mr_bbmri_6slices") + "' -t 300 -o head.ply -q", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const test::Topology topology = test::analyse(test::to_mesh(read_ply(dir / "head.ply")));
  EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  EXPECT_GT(topology.faces, 10000u);
  EXPECT_GT(topology.signed_volume, 0);
}

}  // namespace
}  // namespace mvox
