// Mesh formats through the command line: `mvox extract` and `mvox demo` write PLY, STL and OBJ
// to files and to standard output, chosen by extension or --format, with --triangulate; bad
// choices are usage errors that leave no file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>
#include <vector>

#include "cli_mesh_checks.h"
#include "command_runner.h"
#include "mesh_topology.h"
#include "obj_reader.h"
#include "pipeline/mesh_job.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "stl_reader.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::expect_success;
using test::run_mvox;
using test::ScratchDirectory;

std::size_t triangles_of(const PlyMesh& ply) {
  std::size_t triangles = 0;
  for (std::size_t f = 0; f < ply.face_count(); ++f)
    triangles += ply.face_offsets[f + 1] - ply.face_offsets[f] - 2;
  return triangles;
}

// A torus phantom written as an image stack in `dir`/stack.
void make_stack(const ScratchDirectory& dir) { test::make_phantom_stack(dir, "torus", "40x36x22"); }

TEST(MeshFormatsCli, EveryFormatToAFileAndToStandardOutput) {
  ScratchDirectory dir;
  make_stack(dir);
  const std::string extract = "extract stack -t 128 -q ";
  for (const char* output :
       {"-o mesh.ply", "-o ascii.ply --ascii", "-o triangles.ply --triangulate", "-o mesh.stl",
        "-o mesh.obj", "-o triangles.obj --triangulate"})
    expect_success(extract + output, dir);
  // Standard output: redirected by the shell (run_mvox adds 2>&1, and -q keeps stderr empty).
  for (const char* output : {"-o - > stdout.ply", "-o - --format ply-ascii > stdout_ascii.ply",
                             "-o - --format stl > stdout.stl", "-o - --format obj > stdout.obj",
                             "-o - --format obj --triangulate > stdout_triangles.obj"})
    expect_success(extract + output, dir);

  const PlyMesh ply = read_ply(dir / "mesh.ply");
  ASSERT_GT(ply.face_count(), 500u);
  const test::Topology topology = test::analyse(test::to_mesh(ply));
  ASSERT_TRUE(topology.closed_and_consistent()) << test::describe(topology);

  // PLY pads its header in a file, not on a pipe: compare what it holds.
  for (const char* name : {"ascii.ply", "stdout.ply", "stdout_ascii.ply"}) {
    const PlyMesh other = read_ply(dir / name);
    EXPECT_EQ(other.positions, ply.positions) << name;
    EXPECT_EQ(other.face_indices, ply.face_indices) << name;
  }
  EXPECT_EQ(test::read_file_bytes(dir / "stdout_ascii.ply").rfind("ply\nformat ascii 1.0\n", 0),
            0u);
  const PlyMesh triangulated = read_ply(dir / "triangles.ply");
  EXPECT_EQ(triangulated.vertex_count(), ply.vertex_count());
  EXPECT_EQ(triangulated.face_count(), triangles_of(ply));
  EXPECT_EQ(triangulated.face_indices.size(), 3 * triangulated.face_count());

  // STL and OBJ: byte for byte the same on standard output as in a file.
  for (const auto& [file, piped] : {std::pair<const char*, const char*>{"mesh.stl", "stdout.stl"},
                                    {"mesh.obj", "stdout.obj"},
                                    {"triangles.obj", "stdout_triangles.obj"}})
    EXPECT_EQ(test::read_file_bytes(dir / piped), test::read_file_bytes(dir / file)) << file;

  const test::StlFile stl = test::read_stl(dir / "mesh.stl");
  EXPECT_EQ(stl.triangles.size(), triangulated.face_count());
  EXPECT_EQ(test::normal_problems(stl), "");
  EXPECT_EQ(stl.header.rfind("mvox marching voxels, threshold 128", 0), 0u) << stl.header;
  const test::Topology stl_topology = test::analyse(test::welded(stl));
  EXPECT_EQ(stl_topology.vertices, ply.vertex_count());
  EXPECT_TRUE(stl_topology.closed_and_consistent()) << test::describe(stl_topology);
  EXPECT_EQ(stl_topology.euler(), 0);

  const test::ObjFile obj = test::read_obj(dir / "mesh.obj");
  EXPECT_EQ(obj.positions, ply.positions);
  EXPECT_EQ(obj.faces.size(), ply.face_count());
  ASSERT_FALSE(obj.comments.empty());
  EXPECT_EQ(obj.comments[0].rfind("mvox marching voxels, threshold 128", 0), 0u);
  const test::ObjFile obj_triangles = test::read_obj(dir / "triangles.obj");
  EXPECT_EQ(obj_triangles.faces.size(), triangulated.face_count());

  EXPECT_EQ(dir.listing(),
            "ascii.ply mesh.obj mesh.ply mesh.stl stack stdout.obj stdout.ply stdout.stl "
            "stdout_ascii.ply stdout_triangles.obj triangles.obj triangles.ply ");
}

TEST(MeshFormatsCli, ExtensionIgnoresCaseAndFormatWinsOverIt) {
  ScratchDirectory dir;
  make_stack(dir);
  expect_success("extract stack -t 128 -q -o MESH.STL", dir);
  expect_success("extract stack -t 128 -q -o Mesh.Obj", dir);
  expect_success("extract stack -t 128 -q -o obj_inside.ply --format obj", dir);
  expect_success("extract stack -t 128 -q -o mesh.ply --normals", dir);
  expect_success("extract stack -t 128 -q -o normals.obj --normals", dir);
  EXPECT_GT(test::read_stl(dir / "MESH.STL").triangles.size(), 500u);
  const test::ObjFile obj = test::read_obj(dir / "Mesh.Obj");
  EXPECT_EQ(test::read_obj(dir / "obj_inside.ply").positions, obj.positions);
  // --normals: the same normals in OBJ as in PLY, one vn per v, named by each face corner.
  const test::ObjFile with_normals = test::read_obj(dir / "normals.obj");
  const PlyMesh ply = read_ply(dir / "mesh.ply");
  EXPECT_EQ(with_normals.positions, ply.positions);
  EXPECT_EQ(with_normals.normals, ply.normals);
  ASSERT_EQ(with_normals.face_normals.size(), with_normals.faces.size());
  for (std::size_t f = 0; f < with_normals.faces.size(); ++f)
    ASSERT_EQ(with_normals.face_normals[f], with_normals.faces[f]) << "face " << f;
}

TEST(MeshFormatsCli, DevicesAndPipesWithoutExtensionGetBinaryPly) {
  ScratchDirectory dir;
  make_stack(dir);
  // A regular file without extension is a usage error (below); a device or FIFO is not a name
  // the user chose, so it gets the native format, as "-" does.
  expect_success("extract stack -t 128 -q -o /dev/null", dir);
  ASSERT_EQ(mkfifo((dir / "pipe").c_str(), 0600), 0);
  // run_mvox prefixes "cd DIR &&", which the & would send to the background with mvox: name
  // the FIFO by its full path for the reader.
  const std::string pipe = dir / "pipe";
  expect_success("extract stack -t 128 -q -o pipe & p=$!; cat '" + pipe + "' > '" +
                     (dir / "from_pipe.bin") + "'; wait $p",
                 dir);
  expect_success("extract stack -t 128 -q -o direct.ply", dir);
  const PlyMesh piped = read_ply(dir / "from_pipe.bin");
  const PlyMesh direct = read_ply(dir / "direct.ply");
  EXPECT_GT(direct.face_count(), 100u);
  EXPECT_EQ(piped.positions, direct.positions);
  EXPECT_EQ(piped.face_indices, direct.face_indices);
}

TEST(MeshFormatsCli, SummaryAndStatsSayWhatWasWritten) {
  ScratchDirectory dir;
  make_stack(dir);
  const auto run = run_mvox("extract stack -t 128 -o mesh.stl --stats stl.json", dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::size_t triangles = test::read_stl(dir / "mesh.stl").triangles.size();
  const std::string json = test::read_file_bytes(dir / "stl.json");
  EXPECT_NE(json.find("\"format\": \"stl\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"faces_written\": " + std::to_string(triangles) + ","), std::string::npos)
      << json;
  EXPECT_NE(json.find("\"axes\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]"), std::string::npos) << json;
  EXPECT_NE(run.output.find("written as " + mvox::grouped(triangles) + " triangles (stl)"),
            std::string::npos)
      << run.output;
  // Polygons written as they are: no triangle count in the summary.
  const auto plain = run_mvox("extract stack -t 128 -o mesh.ply", dir.path());
  EXPECT_EQ(plain.output.find("written as"), std::string::npos) << plain.output;
}

TEST(MeshFormatsCli, BadFormatChoicesAreUsageErrorsAndWriteNothing) {
  ScratchDirectory dir;
  make_stack(dir);
  const std::string extract = "extract stack -t 128 ";
  expect_one_line_error(run_mvox(extract + "-o mesh.ply --format vrml", dir.path()), "--format", 2);
  const auto unknown = run_mvox(extract + "-o mesh.xyz", dir.path());
  expect_one_line_error(unknown, "mesh.xyz", 2);
  EXPECT_NE(unknown.output.find("ply|ply-ascii|stl|obj"), std::string::npos) << unknown.output;
  expect_one_line_error(run_mvox(extract + "-o mesh", dir.path()), "'mesh'", 2);
  expect_one_line_error(run_mvox(extract + "-o mesh.stl --ascii", dir.path()), "--ascii", 2);
  expect_one_line_error(run_mvox(extract + "-o mesh.ply --format stl --ascii", dir.path()),
                        "--ascii", 2);
  expect_one_line_error(run_mvox(extract + "--image a.png --format obj", dir.path()), "--format",
                        2);
  expect_one_line_error(run_mvox("demo --size 8 -o demo.vrml", dir.path()), "demo.vrml", 2);
  // A usage error: STL has no vertex normals.
  expect_one_line_error(run_mvox(extract + "-o mesh.stl --normals", dir.path()), "--normals", 2);
  // An option for a mesh with no mesh asked for, as --format is above, and --normals.
  expect_one_line_error(run_mvox(extract + "--image a.png --triangulate", dir.path()),
                        "--triangulate", 2);
  expect_one_line_error(run_mvox(extract + "--image a.png --normals", dir.path()), "--normals", 2);
  EXPECT_EQ(dir.listing(), "stack ");
}

TEST(MeshFormatsCli, DemoWritesEveryFormat) {
  ScratchDirectory dir;
  expect_success("demo --size 40 -q -o demo.stl --image demo.png", dir);
  expect_success("demo --size 40 -q -o demo.obj --triangulate --image demo2.png", dir);
  expect_success("demo --size 40 -q -o demo.ply --image demo3.png --triangulate", dir);
  const test::StlFile stl = test::read_stl(dir / "demo.stl");
  EXPECT_EQ(stl.header.rfind("mvox demo: shepp-logan phantom", 0), 0u) << stl.header;
  EXPECT_EQ(test::normal_problems(stl), "");
  const test::Topology t = test::analyse(test::welded(stl));
  EXPECT_TRUE(t.closed_and_consistent()) << test::describe(t);
  const test::ObjFile obj = test::read_obj(dir / "demo.obj");
  const PlyMesh ply = read_ply(dir / "demo.ply");
  EXPECT_EQ(obj.positions, ply.positions);
  EXPECT_EQ(obj.faces.size(), stl.triangles.size());
  EXPECT_EQ(ply.face_count(), stl.triangles.size());
}

TEST(MeshFormatsCli, HelpShowsFormatAndTriangulate) {
  ScratchDirectory dir;
  for (const char* command : {"extract --help", "demo --help"}) {
    const auto help = run_mvox(command, dir.path());
    EXPECT_EQ(help.exit_code, 0);
    for (const char* text : {"--format", "ply|ply-ascii|stl|obj", "--triangulate", "--ascii"})
      EXPECT_NE(help.output.find(text), std::string::npos) << command << ": " << text;
  }
}

}  // namespace
}  // namespace mvox
