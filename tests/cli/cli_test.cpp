// The mvox command line end to end: a phantom written as an image stack, extracted from files,
// read back from PLY by the strict reader. Bad input has its own suite: bad_input_*_test.cpp.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "command_runner.h"
#include "mesh_topology.h"
#include "mvox_process.h"
#include "phantom_factory.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "simulated_scanner.h"
#include "write/stats_json.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::MvoxProcess;
using test::run_mvox;
using test::ScratchDirectory;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Cli, PhantomStackExtractedFromFilesIsClosedWithTheRightTopology) {
  ScratchDirectory dir;
  auto written = run_mvox("phantom torus -o stack --size 40x36x22 -q", dir.path());
  ASSERT_EQ(written.exit_code, 0) << written.output;
  auto extracted = run_mvox("extract stack -t 128 -o torus.ply --stats torus.json -q", dir.path());
  ASSERT_EQ(extracted.exit_code, 0) << extracted.output;
  EXPECT_EQ(extracted.output, "");  // --quiet

  const test::Mesh mesh = test::to_mesh(read_ply(dir / "torus.ply"));
  const test::Topology t = test::analyse(mesh);
  EXPECT_TRUE(t.closed_and_consistent()) << test::describe(t);
  EXPECT_EQ(t.euler(), 0) << test::describe(t);
  EXPECT_EQ(t.components, 1u);
  EXPECT_GT(t.signed_volume, 0);

  // The same phantom streamed in memory: the file path lost and reordered nothing.
  const auto torus = sim::make_phantom("torus", {40, 36, 22}, 1);
  sim::SimulatedScanner scanner(*torus);
  const test::Mesh direct = test::extract(scanner, 128);
  ASSERT_EQ(mesh.vertices.size(), direct.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    ASSERT_TRUE(test::same_position(mesh.vertices[i], direct.vertices[i])) << "vertex " << i;
  EXPECT_EQ(mesh.polygons, direct.polygons);

  const std::string json = read_text(dir / "torus.json");
  EXPECT_NE(json.find("\"dimensions\": [40, 36, 22]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"vertices\": " + std::to_string(mesh.vertices.size())), std::string::npos);
  EXPECT_NE(json.find("\"polygons\": " + std::to_string(mesh.polygons.size())), std::string::npos);
  for (const char* field : {"\"threshold\": 128", "\"inner_voxels\"", "\"polygons_by_size\"",
                            "\"time_seconds\"", "\"peak_memory_bytes\"", "\"engine\": \"fast\""})
    EXPECT_NE(json.find(field), std::string::npos) << field;
}

// What `command` prints (through the shell).
std::string command_output(const std::string& command) {
  std::string output;
  if (std::FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    pclose(pipe);
  }
  return output;
}

// Strings in JSON must be UTF-8 without raw control characters; names on disk are any bytes.
TEST(Cli, JsonStringsAreValidWhateverTheBytes) {
  EXPECT_EQ(json_string("plain/é/€/𝄞"), "\"plain/é/€/𝄞\"");  // UTF-8 passes as it is
  EXPECT_EQ(json_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(json_string(std::string("\n\t\x1f\x7f\0z", 6)),
            "\"\\u000a\\u0009\\u001f\\u007f\\u0000z\"");
  const std::string replacement = "\xef\xbf\xbd";  // U+FFFD, for each byte that is not UTF-8
  EXPECT_EQ(json_string("\xff"), "\"" + replacement + "\"");
  EXPECT_EQ(json_string("caf\xe9!"), "\"caf" + replacement + "!\"");            // Latin-1
  EXPECT_EQ(json_string("\xc0\xaf"), "\"" + replacement + replacement + "\"");  // overlong '/'
  EXPECT_EQ(json_string("\xed\xa0\x80"), "\"" + replacement + replacement + replacement + "\"");
  EXPECT_EQ(json_string("\xf4\x90\x80\x80"),
            "\"" + replacement + replacement + replacement + replacement + "\"");  // past U+10FFFF
  EXPECT_EQ(json_string("\xe2\x82"), "\"" + replacement + replacement + "\"");     // cut short
  EXPECT_EQ(json_string("\xe2\x82z"), "\"" + replacement + replacement + "z\"");
}

// The report of a run on a folder whose name is not UTF-8 and holds a newline parses as JSON.
TEST(Cli, StatsReportIsValidJsonWhateverTheFileNames) {
  if (std::system("command -v python3 >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3 is not installed: its strict JSON parser checks the report";
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x8 -q", dir.path()).exit_code, 0);
  const std::string name = "stack\xff\n\xc3\xa9";  // a Latin-1 byte, a newline, UTF-8 é
  std::filesystem::rename(dir / "stack", dir / name);
  MvoxProcess mvox(
      {"extract", name, "-t", "128", "-o", name + ".ply", "--stats", "report.json", "-q"},
      dir.path());
  const MvoxProcess::Ending ending = mvox.finish();
  ASSERT_EQ(ending.exit_code, 0) << ending.errors;
  const std::string json = read_text(dir / "report.json");
  // Strict: UTF-8 only, no raw control character in a string, no NaN.
  const std::string check =
      "cd '" + dir.path().string() +
      "' && python3 -c 'import json, sys; json.loads(open(sys.argv[1], encoding=\"utf-8\", "
      "errors=\"strict\").read(), parse_constant=lambda c: 1 / 0); print(\"valid\")' "
      "report.json 2>&1";
  const std::string parsed = command_output(check);
  EXPECT_EQ(parsed, "valid\n") << json;
  EXPECT_NE(json.find("\"input\": \"stack\xef\xbf\xbd\\u000a\xc3\xa9\""), std::string::npos)
      << json;
  EXPECT_NE(json.find("\"output\": \"stack\xef\xbf\xbd\\u000a\xc3\xa9.ply\""), std::string::npos)
      << json;
}

TEST(Cli, LiteralEngineAsciiAndSpacingOptions) {
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom blobs -o stack --size 30x26x20 --bits 16 -q", dir.path()).exit_code,
            0);
  const std::string threshold =
      std::to_string(sim::sample_threshold(0.5, sim::default_scan_options(SampleType::u16)));
  ASSERT_EQ(run_mvox("extract stack -t " + threshold + " -o fast.ply -q", dir.path()).exit_code, 0);
  ASSERT_EQ(
      run_mvox("extract stack -t " + threshold + " -o literal.ply --engine literal -q", dir.path())
          .exit_code,
      0);
  ASSERT_EQ(run_mvox("extract stack -t " + threshold + " -o ascii.ply --ascii --spacing 1,1,2.5 -q",
                     dir.path())
                .exit_code,
            0);
  const PlyMesh fast = read_ply(dir / "fast.ply");
  const PlyMesh literal = read_ply(dir / "literal.ply");
  const PlyMesh ascii = read_ply(dir / "ascii.ply");
  EXPECT_GT(fast.face_count(), 100u);
  EXPECT_EQ(fast.positions, literal.positions);
  EXPECT_EQ(fast.face_indices, literal.face_indices);
  EXPECT_EQ(read_text(dir / "ascii.ply").rfind("ply\nformat ascii 1.0\n", 0), 0u);
  ASSERT_EQ(ascii.positions.size(), fast.positions.size());
  for (std::size_t i = 0; i < fast.positions.size(); ++i) {
    EXPECT_EQ(ascii.positions[i][0], fast.positions[i][0]);
    EXPECT_EQ(ascii.positions[i][2], fast.positions[i][2] * 2.5f);
  }
  EXPECT_EQ(ascii.face_indices, fast.face_indices);
}

TEST(Cli, MarchingCubesMethodWritesTrianglesWithInterpolatedVertices) {
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom torus -o stack --size 40x36x22 -q", dir.path()).exit_code, 0);
  auto voxels = run_mvox("extract stack -t 128 -o voxels.ply -q", dir.path());
  ASSERT_EQ(voxels.exit_code, 0) << voxels.output;
  auto cubes =
      run_mvox("extract stack -t 128 --method cubes -o cubes.ply --stats cubes.json", dir.path());
  ASSERT_EQ(cubes.exit_code, 0) << cubes.output;
  EXPECT_NE(cubes.output.find("triangles (marching cubes)"), std::string::npos) << cubes.output;

  const PlyMesh from_voxels = read_ply(dir / "voxels.ply");
  const PlyMesh from_cubes = read_ply(dir / "cubes.ply");
  // The same vertices, moved along their edges; triangles only.
  ASSERT_EQ(from_cubes.positions.size(), from_voxels.positions.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < from_cubes.positions.size(); ++i)
    moved += from_cubes.positions[i] != from_voxels.positions[i];
  EXPECT_GT(moved, from_cubes.positions.size() / 2);
  for (std::size_t f = 0; f < from_cubes.face_count(); ++f)
    ASSERT_EQ(from_cubes.face_offsets[f + 1] - from_cubes.face_offsets[f], 3u) << "face " << f;
  // What the engine gives in memory, through the file unchanged.
  const auto torus = sim::make_phantom("torus", {40, 36, 22}, 1);
  sim::SimulatedScanner scanner(*torus);
  EngineOptions options;
  options.method = SurfaceMethod::cubes;
  const test::Mesh direct = test::extract(scanner, 128, options);
  EXPECT_EQ(test::to_mesh(from_cubes).polygons, direct.polygons);
  const std::string json = read_text(dir / "cubes.json");
  EXPECT_NE(json.find("\"method\": \"cubes\""), std::string::npos) << json;

  // Options that only marching voxels has are refused, not ignored.
  expect_one_line_error(
      run_mvox("extract stack -t 128 --method cubes --engine literal -o x.ply", dir.path()),
      "--method cubes", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --method squares -o x.ply", dir.path()),
                        "--method", 2);
  EXPECT_EQ(dir.listing(), "cubes.json cubes.ply stack voxels.ply ");
}

TEST(Cli, OriginPlacesTheMeshAndAThresholdOutsideTheSampleRangeIsRefused) {
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 20x18x12 -q", dir.path()).exit_code, 0);
  ASSERT_EQ(run_mvox("extract stack -t 128 -o plain.ply -q", dir.path()).exit_code, 0);
  const auto placed = run_mvox(
      "extract stack -t 128 -o placed.ply --spacing 1,1,2 --origin 10,-5,2.5 -q "
      "--stats placed.json",
      dir.path());
  ASSERT_EQ(placed.exit_code, 0) << placed.output;
  const PlyMesh plain = read_ply(dir / "plain.ply");
  const PlyMesh moved = read_ply(dir / "placed.ply");
  ASSERT_EQ(moved.positions.size(), plain.positions.size());
  for (std::size_t i = 0; i < plain.positions.size(); ++i) {
    EXPECT_FLOAT_EQ(moved.positions[i][0], 10 + plain.positions[i][0]);
    EXPECT_FLOAT_EQ(moved.positions[i][1], -5 + plain.positions[i][1]);
    EXPECT_FLOAT_EQ(moved.positions[i][2], 2.5f + 2 * plain.positions[i][2]);
  }
  EXPECT_NE(read_text(dir / "placed.json").find("\"origin\": [10, -5, 2.5]"), std::string::npos)
      << read_text(dir / "placed.json");

  // 8-bit slices: above 255 nothing is inner, at or below 0 everything is.
  expect_one_line_error(run_mvox("extract stack -t 300 -o x.ply", dir.path()), "stack");
  expect_one_line_error(run_mvox("extract stack -t 0 -o x.ply", dir.path()), "stack");
  expect_one_line_error(run_mvox("extract stack -t 128 -o x.ply --origin 1,nan,0", dir.path()),
                        "--origin", 2);
  EXPECT_EQ(dir.listing(), "placed.json placed.ply plain.ply stack ");
}

TEST(Cli, DemoNeedsNoFilesAndWritesDemoPly) {
  ScratchDirectory dir;
  const auto result = run_mvox("demo --size 48", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("shepp-logan"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("demo.ply"), std::string::npos) << result.output;
  const test::Topology t = test::analyse(test::to_mesh(read_ply(dir / "demo.ply")));
  EXPECT_TRUE(t.closed_and_consistent()) << test::describe(t);
  EXPECT_GE(t.components, 3u);
}

TEST(Cli, HelpListsTheCommandsAndOptions) {
  ScratchDirectory dir;
  const auto top = run_mvox("--help", dir.path());
  EXPECT_EQ(top.exit_code, 0);
  for (const char* word : {"extract", "demo", "phantom", "render"})
    EXPECT_NE(top.output.find(word), std::string::npos);
  const auto extract = run_mvox("extract --help", dir.path());
  EXPECT_EQ(extract.exit_code, 0);
  for (const char* option :
       {"--threshold", "--raw", "--engine", "--surface", "--stats", "--ascii", "--spacing",
        "--image", "--view", "--frames", "--every", "--show", "--normals"})
    EXPECT_NE(extract.output.find(option), std::string::npos) << option;
}

}  // namespace
}  // namespace mvox
