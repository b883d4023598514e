// The mesh writers (PLY, STL, OBJ) and the world transform they share: every format read back
// by a strict reader of its own (tests/support) with the PLY's counts, the STL header and
// normals, standard output, all-or-nothing files, and placement by spacing, origin and axes,
// mirroring included.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "mesh_capture.h"
#include "mesh_topology.h"
#include "mvox/fan_out_sink.h"
#include "obj_reader.h"
#include "phantom_factory.h"
#include "picture/normal_window.h"
#include "pipeline/pipeline.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "simulated_scanner.h"
#include "stdout_redirect.h"
#include "stl_reader.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/obj_writer.h"
#include "write/mesh/ply_writer.h"
#include "write/mesh/stl_writer.h"
#include "write/mesh/vertex_placement.h"
#include "write/mesh/world_transform.h"

namespace mvox {
namespace {

using test::read_bytes;
using test::write_bytes;

using test::ScratchDirectory;

// HELPERS -------------------------------------------------------------------------------------

// Streams phantom `name` on `grid` through the engine (polygons by value, as STL and
// --triangulate need) into `sinks`, with the normal window when `window` is given.
void stream_phantom(const std::string& name, sim::Grid grid, std::vector<PolygonSink*> sinks,
                    NormalWindow* window = nullptr, const double spacing[3] = nullptr) {
  const auto phantom = sim::make_phantom(name, grid, 7);
  sim::ScanOptions scan;
  scan.partial_volume = window != nullptr;  // smooth edges for gradient normals
  if (spacing)
    for (int axis = 0; axis < 3; ++axis) scan.spacing[axis] = spacing[axis];
  sim::SimulatedScanner scanner(*phantom, scan);
  FanOutSink fan_out;
  for (PolygonSink* sink : sinks) ASSERT_TRUE(fan_out.add(sink));
  PipelineSinks pipeline_sinks;
  pipeline_sinks.mesh = &fan_out;
  if (window) pipeline_sinks.window = &window->window();
  EngineOptions options;
  options.polygon_geometry = true;
  const PipelineResult result =
      run_pipeline(scanner, sim::sample_threshold(sim::default_density_threshold(name), scan),
                   options, pipeline_sinks, name);
  ASSERT_EQ(result.status, Status::ok);
}

std::size_t triangles_of(const PlyMesh& ply) {
  std::size_t triangles = 0;
  for (std::size_t f = 0; f < ply.face_count(); ++f)
    triangles += ply.face_offsets[f + 1] - ply.face_offsets[f] - 2;
  return triangles;
}

MeshWriterOptions described(const std::string& comment, bool triangulate = false) {
  MeshWriterOptions options;
  options.comments = {comment};
  options.triangulate = triangulate;
  return options;
}

// EVERY FORMAT --------------------------------------------------------------------------------

TEST(MeshFormats, EveryFormatReadsBackWithThePlysCounts) {
  ScratchDirectory dir;
  const std::string comment = "mvox marching voxels, threshold 128";
  struct Output {
    const char* file;
    MeshFormat format;
    bool triangulate;
  };
  const Output outputs[] = {
      {"mesh.ply", MeshFormat::ply, false},     {"ascii.ply", MeshFormat::ply_ascii, false},
      {"triangles.ply", MeshFormat::ply, true}, {"mesh.obj", MeshFormat::obj, false},
      {"triangles.obj", MeshFormat::obj, true}, {"mesh.stl", MeshFormat::stl, false}};
  std::vector<std::unique_ptr<MeshWriter>> writers;
  std::vector<PolygonSink*> sinks;
  for (const Output& output : outputs) {
    writers.push_back(
        open_mesh_writer(dir / output.file, output.format, described(comment, output.triangulate)));
    sinks.push_back(writers.back().get());
  }
  // A torus (one handle) on an odd, asymmetric grid.
  stream_phantom("torus", {41, 37, 23}, sinks);
  for (auto& writer : writers) writer->finish();

  const PlyMesh ply = read_ply(dir / "mesh.ply");
  const test::Topology topology = test::analyse(test::to_mesh(ply));
  ASSERT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  ASSERT_EQ(topology.euler(), 0);
  ASSERT_GT(ply.face_count(), 500u);
  EXPECT_GT(triangles_of(ply), ply.face_count()) << "the torus should have polygons, not only "
                                                    "triangles";

  const PlyMesh ascii = read_ply(dir / "ascii.ply");
  EXPECT_EQ(ascii.positions, ply.positions);
  EXPECT_EQ(ascii.face_offsets, ply.face_offsets);
  EXPECT_EQ(ascii.face_indices, ply.face_indices);

  const PlyMesh triangulated = read_ply(dir / "triangles.ply");
  EXPECT_EQ(triangulated.positions, ply.positions);
  EXPECT_EQ(triangulated.face_count(), triangles_of(ply));
  EXPECT_EQ(triangulated.face_indices.size(), 3 * triangles_of(ply));
  const test::Topology triangle_topology = test::analyse(test::to_mesh(triangulated));
  EXPECT_TRUE(triangle_topology.closed_and_consistent()) << test::describe(triangle_topology);
  EXPECT_EQ(triangle_topology.euler(), 0);

  // OBJ: the same vertices (shortest float text reads back exactly) and faces, 1-based.
  const test::ObjFile obj = test::read_obj(dir / "mesh.obj");
  EXPECT_EQ(obj.comments, std::vector<std::string>{comment});
  EXPECT_TRUE(obj.comments_first);
  EXPECT_EQ(obj.positions, ply.positions);
  EXPECT_TRUE(obj.normals.empty());
  ASSERT_EQ(obj.faces.size(), ply.face_count());
  for (std::size_t f = 0; f < ply.face_count(); ++f)
    ASSERT_EQ(obj.faces[f],
              std::vector<std::uint32_t>(ply.face_indices.begin() + ply.face_offsets[f],
                                         ply.face_indices.begin() + ply.face_offsets[f + 1]))
        << "face " << f;
  const test::ObjFile obj_triangles = test::read_obj(dir / "triangles.obj");
  EXPECT_EQ(obj_triangles.positions, ply.positions);
  EXPECT_EQ(test::to_mesh(obj_triangles).polygons, test::to_mesh(triangulated).polygons);

  // STL: one record per triangle of the triangulated PLY, same vertices in the same order.
  const std::string stl_bytes = test::read_file_bytes(dir / "mesh.stl");
  const test::StlFile stl = test::parse_stl(stl_bytes);
  ASSERT_EQ(stl.triangles.size(), triangulated.face_count());
  EXPECT_EQ(stl_bytes.size(), 84 + 50 * triangulated.face_count());
  EXPECT_EQ(stl.header.rfind(comment, 0), 0u) << stl.header;
  EXPECT_NE(stl.header.rfind("solid", 0), 0u);
  EXPECT_EQ(test::normal_problems(stl), "");
  for (std::size_t t = 0; t < stl.triangles.size(); ++t) {
    EXPECT_EQ(stl.triangles[t].attribute, 0u);
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(stl.triangles[t].vertices[k],
                triangulated.positions[triangulated.face_indices[3 * t + k]])
          << "triangle " << t << " corner " << k;
  }
  const test::Topology stl_topology = test::analyse(test::welded(stl));
  EXPECT_EQ(stl_topology.vertices, ply.vertex_count());
  EXPECT_TRUE(stl_topology.closed_and_consistent()) << test::describe(stl_topology);
  // The same triangles as the triangulated PLY's, so the same volume (polygons that are not
  // flat enclose a little more or less depending on how they are split).
  EXPECT_NEAR(stl_topology.signed_volume, triangle_topology.signed_volume,
              1e-9 * triangle_topology.signed_volume);
  EXPECT_GT(stl_topology.signed_volume, 0);
}

TEST(MeshFormats, StandardOutputGetsTheSameBytesAsAFile) {
  ScratchDirectory dir;
  for (MeshFormat format : {MeshFormat::stl, MeshFormat::obj}) {
    SCOPED_TRACE(mesh_format_name(format));
    auto file_writer = open_mesh_writer(dir / "mesh", format, described("mvox test"));
    {
      test::StdoutRedirect redirect(dir / "stdout");
      auto stdout_writer = open_mesh_writer("-", format, described("mvox test"));
      // The same batches to both, as two runs of the engine would send them.
      stream_phantom("sphere", {19, 17, 13}, {file_writer.get(), stdout_writer.get()});
      stdout_writer->finish();
    }
    file_writer->finish();
    const std::string bytes = test::read_file_bytes(dir / "mesh");
    EXPECT_GT(bytes.size(), 1000u);
    EXPECT_EQ(test::read_file_bytes(dir / "stdout"), bytes);
  }
}

TEST(MeshFormats, NothingAppearsBeforeFinishAndARefusalKeepsThePreviousFile) {
  ScratchDirectory dir;
  Vertex vertices[4];
  for (int i = 0; i < 4; ++i) vertices[i].x = 0.5f + i;
  Polygon bad;
  bad.vertex_count = 3;
  bad.vertices[0] = 0;
  bad.vertices[1] = 1;
  bad.vertices[2] = 4;  // never sent
  for (MeshFormat format : {MeshFormat::ply, MeshFormat::stl, MeshFormat::obj}) {
    SCOPED_TRACE(mesh_format_name(format));
    const std::string target = dir / "mesh";
    write_bytes(target, "previous mesh");
    {
      auto writer = open_mesh_writer(target, format, {});
      ASSERT_EQ(writer->consume_vertices(vertices, 4), Status::ok);
      EXPECT_EQ(writer->consume_polygons(&bad, 1), Status::sink_refused);
      ASSERT_NE(writer->error(), nullptr);
      EXPECT_NE(std::string(writer->error()->what()).find("refers to vertex 4"), std::string::npos);
      EXPECT_EQ(writer->consume_vertices(vertices, 1), Status::sink_refused);  // final
      EXPECT_EQ(test::read_file_bytes(target), "previous mesh");
      EXPECT_THROW(writer->finish(), Error);
    }
    EXPECT_EQ(test::read_file_bytes(target), "previous mesh");
    EXPECT_EQ(dir.listing(), "mesh ") << "a temporary was left behind";
  }
}

TEST(MeshFormats, PolygonsLeftWithoutTheirGeometryAreAnError) {
  ScratchDirectory dir;
  Vertex vertices[3];
  for (int i = 0; i < 3; ++i) vertices[i].x = 0.5f + i;
  Polygon triangle;
  triangle.vertex_count = 3;
  for (int i = 0; i < 3; ++i) triangle.vertices[i] = static_cast<std::uint32_t>(i);
  // STL and --triangulate need positions per face, which only polygon geometry brings.
  for (const bool stl : {true, false}) {
    auto writer = stl ? open_mesh_writer(dir / "mesh.stl", MeshFormat::stl, {})
                      : open_mesh_writer(dir / "mesh.obj", MeshFormat::obj, described("t", true));
    EXPECT_TRUE(writer->needs_polygon_geometry());
    ASSERT_EQ(writer->consume_vertices(vertices, 3), Status::ok);
    ASSERT_EQ(writer->consume_polygons(&triangle, 1), Status::ok);
    try {
      writer->finish();
      ADD_FAILURE() << "no error";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("without their geometry"), std::string::npos)
          << error.what();
    }
  }
  EXPECT_FALSE(open_mesh_writer(dir / "mesh.ply", MeshFormat::ply, {})->needs_polygon_geometry());
  EXPECT_EQ(dir.listing(), "");
}

// A square lying in a cube face (z = 0) has no split whose diagonal avoids the face: STL and
// --triangulate refuse it as an internal error, naming what it is, and leave no file. (The
// engine never makes one: polygon_triangulation_test checks every configuration.)
TEST(MeshFormats, APolygonNoFanCanSplitIsRefusedByTheFormatsThatSplit) {
  ScratchDirectory dir;
  Vertex vertices[4];
  const float corners[4][2] = {{0.5f, 0}, {1, 0.5f}, {0.5f, 1}, {0, 0.5f}};
  PolygonGeometry geometry;
  geometry.vertex_count = 4;
  Polygon square;
  square.vertex_count = 4;
  for (int k = 0; k < 4; ++k) {
    vertices[k] = {corners[k][0], corners[k][1], 0.0f};
    geometry.vertices[k] = vertices[k];
    square.vertices[k] = static_cast<std::uint32_t>(k);
  }
  for (const bool stl : {true, false}) {
    auto writer = stl ? open_mesh_writer(dir / "mesh.stl", MeshFormat::stl, {})
                      : open_mesh_writer(dir / "mesh.obj", MeshFormat::obj, described("t", true));
    ASSERT_EQ(writer->consume_vertices(vertices, 4), Status::ok);
    ASSERT_EQ(writer->consume_polygons(&square, 1), Status::ok);
    EXPECT_EQ(writer->consume_polygon_geometry(&geometry, 1), Status::sink_refused);
    try {
      writer->finish();
      ADD_FAILURE() << "no error";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what())
                    .find("a 4-gon cannot be split without a diagonal on a cube face"),
                std::string::npos)
          << error.what();
    }
  }
  EXPECT_EQ(dir.listing(), "");
}

// STL -----------------------------------------------------------------------------------------

TEST(StlWriter, HeaderSaysWhatMadeItAndNeverStartsWithSolid) {
  ScratchDirectory dir;
  const std::string long_comment(100, 'x');
  struct Case {
    std::vector<std::string> comments;
    std::string starts;
  };
  const Case cases[] = {
      {{}, "mvox"},
      {{"mvox marching voxels, threshold 600"}, "mvox marching voxels, threshold 600"},
      {{"solid block"}, "mvox: solid block"},
      {{"SOLID"}, "mvox: SOLID"},
      {{long_comment}, long_comment.substr(0, 80)}};
  for (const Case& c : cases) {
    MeshWriterOptions options;
    options.comments = c.comments;
    StlWriter writer(dir / "empty.stl", options);
    writer.finish();
    const std::string bytes = test::read_file_bytes(dir / "empty.stl");
    ASSERT_EQ(bytes.size(), 84u);  // an empty mesh: the header and a count of 0
    const test::StlFile stl = test::parse_stl(bytes);
    EXPECT_TRUE(stl.triangles.empty());
    EXPECT_EQ(stl.header.rfind(c.starts, 0), 0u) << stl.header;
    EXPECT_NE(stl.header.substr(0, 5), "solid");
    EXPECT_EQ(stl.header.find_first_not_of(' ', c.starts.size()), std::string::npos)
        << "padded with spaces: " << stl.header;
  }
}

TEST(StlWriter, RefusesVertexNormalsItCannotStore) {
  ScratchDirectory dir;
  const VolumeInfo volume = [] {
    VolumeInfo v;
    v.width = v.height = v.depth = 4;
    return v;
  }();
  NormalWindow window(volume, {1, 1, 1}, "volume");
  MeshWriterOptions options;
  options.normals = &window.normals();
  try {
    StlWriter writer(dir / "mesh.stl", options);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.subject(), "--normals");
  }
  EXPECT_EQ(dir.listing(), "");
}

// The strict readers must refuse what is wrong, or the checks above would prove nothing.
TEST(StlWriter, TheTestsReaderRefusesWrongSizes) {
  std::string bytes(84, ' ');
  bytes[80] = 1;  // one triangle announced, none there
  bytes[81] = bytes[82] = bytes[83] = 0;
  EXPECT_THROW(test::parse_stl(bytes), std::runtime_error);
  bytes.append(50, '\0');
  EXPECT_NO_THROW(test::parse_stl(bytes));
  bytes.push_back('\0');
  EXPECT_THROW(test::parse_stl(bytes), std::runtime_error);
}

// OBJ -----------------------------------------------------------------------------------------

TEST(ObjWriter, TheTestsReaderRefusesWhatIsNotStrictObj) {
  EXPECT_NO_THROW(test::parse_obj("# c\nv 1 2 3\nv 0 1 0\nv 1 0 0\nf 1 2 3\n"));
  for (const char* bad :
       {"v 1 2\n", "v 1 2 3 4\n", "v 1  2 3\n", "v 1 2 nan\n", "v 1 2 3x\n",
        "v 1 2 3\nv 0 1 0\nf 1 2 3\n", "v 1 2 3\nv 0 1 0\nv 1 0 0\nf 1 2\n",
        "v 1 2 3\nv 0 1 0\nv 1 0 0\nf 0 1 2\n", "v 1 2 3\nv 0 1 0\nv 1 0 0\nf 1 2 -3\n",
        "v 1 2 3\nv 0 1 0\nv 1 0 0\nvn 0 0 1\nf 1//1 2 3\n",
        "v 1 2 3\nv 0 1 0\nv 1 0 0\nf 1//1 2//1 3//1\n", "vt 0 0\n", "\n", "v 1 2 3"})
    EXPECT_THROW(test::parse_obj(bad), std::runtime_error) << bad;
}

TEST(ObjWriter, NormalsFollowTheirVertexAndFacesNameThem) {
  ScratchDirectory dir;
  const sim::Grid grid = {21, 19, 15};
  VolumeInfo volume;
  volume.width = grid.width;
  volume.height = grid.height;
  volume.depth = grid.depth;
  NormalWindow window(volume, {1, 1, 1}, "sphere");
  MeshWriterOptions options = described("normals");
  options.normals = &window.normals();
  ObjWriter obj(dir / "mesh.obj", options);
  PlyWriterOptions ply_options;
  static_cast<MeshWriterOptions&>(ply_options) = options;
  PlyWriter ply(dir / "mesh.ply", ply_options);
  stream_phantom("sphere", grid, {&obj, &ply}, &window);
  obj.finish();
  ply.finish();
  const test::ObjFile read = test::read_obj(dir / "mesh.obj");
  const PlyMesh reference = read_ply(dir / "mesh.ply");
  ASSERT_EQ(read.normals.size(), read.positions.size());
  EXPECT_EQ(read.normals, reference.normals);
  for (std::size_t f = 0; f < read.faces.size(); ++f)
    EXPECT_EQ(read.face_normals[f], read.faces[f]);
  // Each "vn" line right after its "v" line.
  const std::string text = test::read_file_bytes(dir / "mesh.obj");
  std::size_t v_lines = 0;
  for (std::size_t at = text.find("\nv "); at != std::string::npos;
       at = text.find("\nv ", at + 1)) {
    ++v_lines;
    const std::size_t next = text.find('\n', at + 1);
    ASSERT_EQ(text.compare(next + 1, 3, "vn "), 0) << "after vertex line " << v_lines;
  }
  EXPECT_EQ(v_lines, read.positions.size());
}

// WORLD TRANSFORM -----------------------------------------------------------------------------

// A quarter turn about z: voxel x runs along world +y, voxel y along world -x.
WorldTransform turned_spaced_and_shifted() {
  WorldTransform t;
  t.spacing = {0.5, 2.0, 3.0};
  t.origin = {10.0, -3.0, 7.0};
  t.axes = {{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}};
  return t;
}

TEST(WorldTransform, SpacingOriginAndAxesPlaceVerticesWhereExpected) {
  // Worked by hand: (1.5, 2, 3) -> origin + 0.75 * (+y) + 4 * (-x) + 9 * (+z).
  const WorldTransform t = turned_spaced_and_shifted();
  EXPECT_EQ(t.position(1.5f, 2.0f, 3.0f), (Vector3d{6.0, -2.25, 16.0}));
  EXPECT_FALSE(t.mirrors());
  EXPECT_FALSE(t.is_axis_aligned());

  // The same through a writer, for every vertex of a phantom, against the identity's output.
  ScratchDirectory dir;
  PlyWriterOptions placed;
  placed.transform = t;
  PlyWriter plain(dir / "plain.ply");
  PlyWriter turned(dir / "turned.ply", placed);
  stream_phantom("blobs", {23, 19, 17}, {&plain, &turned});
  plain.finish();
  turned.finish();
  const PlyMesh voxel = read_ply(dir / "plain.ply");
  const PlyMesh world = read_ply(dir / "turned.ply");
  ASSERT_EQ(world.vertex_count(), voxel.vertex_count());
  for (std::size_t i = 0; i < voxel.vertex_count(); ++i) {
    const auto& v = voxel.positions[i];
    const std::array<float, 3> expected = {static_cast<float>(10.0 - 2.0 * v[1]),
                                           static_cast<float>(-3.0 + 0.5 * v[0]),
                                           static_cast<float>(7.0 + 3.0 * v[2])};
    ASSERT_EQ(world.positions[i], expected) << "vertex " << i;
  }
  // A rotation keeps the winding: the same faces, and the volume scaled by the spacing.
  EXPECT_EQ(world.face_indices, voxel.face_indices);
  const double plain_volume = test::analyse(test::to_mesh(voxel)).signed_volume;
  EXPECT_NEAR(test::analyse(test::to_mesh(world)).signed_volume, 3.0 * plain_volume,
              1e-4 * plain_volume);
}

TEST(WorldTransform, IdentityAxesGiveExactlyOriginPlusSpacingTimesVoxel) {
  WorldTransform t;
  t.spacing = {0.1, 0.3, 1.0 / 3.0};
  t.origin = {-12.345, 1e-3, 7e6};
  EXPECT_TRUE(t.is_axis_aligned());
  for (float v : {0.0f, 0.5f, 2047.5f, 123456.5f}) {
    const Vector3d p = t.position(v, v + 1, v + 2);
    EXPECT_EQ(p[0], -12.345 + 0.1 * v);
    EXPECT_EQ(p[1], 1e-3 + 0.3 * (v + 1));
    EXPECT_EQ(p[2], 7e6 + (1.0 / 3.0) * (v + 2));
    EXPECT_EQ(t.axis_aligned_position(v, v + 1, v + 2), p);  // the writers' fast path
  }
}

// place() with and without normals gives the same floats and names the same first vertex
// beyond float's range: a guard for any faster path for the common case (identity axes, no
// normals), such as the one tried and reverted in 3219ff2.
TEST(VertexPlacement, WithAndWithoutNormalsPlaceAlikeAndNameTheFirstVertexBeyondFloatsRange) {
  WorldTransform t;
  t.spacing = {1e36, 0.3, 1.0 / 3.0};
  t.origin = {-12.345, 1e-3, 7e6};
  t.check("test");
  const VertexPlacement fast(t, false), careful(t, true);
  std::vector<Vertex> vertices;
  for (float v : {0.0f, 0.5f, 2.5f, 123.5f}) vertices.push_back({v, v + 1, v + 2});
  const std::vector<glm::vec3> normals(8, glm::vec3(0, 0, 1));
  std::vector<WorldVertex> a(8), b(8);  // room for the vertices added below
  ASSERT_EQ(fast.place(vertices.data(), nullptr, vertices.size(), a.data()), vertices.size());
  ASSERT_EQ(careful.place(vertices.data(), normals.data(), vertices.size(), b.data()),
            vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vector3d p = t.axis_aligned_position(vertices[i].x, vertices[i].y, vertices[i].z);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(a[i].position[axis], static_cast<float>(p[axis]));
      EXPECT_EQ(b[i].position[axis], static_cast<float>(p[axis]));
    }
  }
  // 1000 * 1e36 along x passes float's largest value (3.4e38): vertex 4 of 5.
  vertices.push_back({1000.0f, 0.0f, 0.0f});
  EXPECT_EQ(fast.place(vertices.data(), nullptr, vertices.size(), a.data()), 4u);
  EXPECT_EQ(careful.place(vertices.data(), normals.data(), vertices.size(), b.data()), 4u);
  vertices.push_back({0.0f, 0.0f, 0.0f});  // one inside after it changes nothing
  EXPECT_EQ(fast.place(vertices.data(), nullptr, vertices.size(), a.data()), 4u);
}

TEST(WorldTransform, MirroringAxesReverseTheWindingSoTheVolumeStaysPositive) {
  ScratchDirectory dir;
  PlyWriterOptions mirrored;
  mirrored.transform.axes = {{{1, 0, 0}, {0, -1, 0}, {0, 0, 1}}};  // rows counted upwards
  ASSERT_TRUE(mirrored.transform.mirrors());
  MeshWriterOptions mirrored_stl;
  mirrored_stl.transform = mirrored.transform;
  PlyWriter plain(dir / "plain.ply");
  PlyWriter flipped(dir / "flipped.ply", mirrored);
  StlWriter flipped_stl(dir / "flipped.stl", mirrored_stl);
  stream_phantom("torus", {31, 27, 19}, {&plain, &flipped, &flipped_stl});
  plain.finish();
  flipped.finish();
  flipped_stl.finish();

  const PlyMesh a = read_ply(dir / "plain.ply");
  const PlyMesh b = read_ply(dir / "flipped.ply");
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  for (std::size_t i = 0; i < a.vertex_count(); ++i)
    ASSERT_EQ(b.positions[i],
              (std::array<float, 3>{a.positions[i][0], -a.positions[i][1], a.positions[i][2]}));
  // Each face: the same first vertex, the others in reverse order.
  ASSERT_EQ(a.face_offsets, b.face_offsets);
  for (std::size_t f = 0; f < a.face_count(); ++f) {
    const std::uint32_t begin = a.face_offsets[f], n = a.face_offsets[f + 1] - begin;
    for (std::uint32_t k = 0; k < n; ++k)
      ASSERT_EQ(b.face_indices[begin + k], a.face_indices[begin + (n - k) % n]) << "face " << f;
  }
  const test::Topology ta = test::analyse(test::to_mesh(a));
  const test::Topology tb = test::analyse(test::to_mesh(b));
  EXPECT_TRUE(tb.closed_and_consistent()) << test::describe(tb);
  EXPECT_GT(tb.signed_volume, 0);
  EXPECT_NEAR(tb.signed_volume, ta.signed_volume, 1e-6 * ta.signed_volume);

  const test::StlFile stl = test::read_stl(dir / "flipped.stl");
  EXPECT_EQ(test::normal_problems(stl), "");
  const test::Topology ts = test::analyse(test::welded(stl));
  EXPECT_TRUE(ts.closed_and_consistent()) << test::describe(ts);
  EXPECT_NEAR(ts.signed_volume, ta.signed_volume, 1e-6 * ta.signed_volume);
}

// Normals are gradients: they turn with the axes (rotations and mirrors alike), and through a
// shear they stay perpendicular to the sheared surface (the inverse transpose).
TEST(WorldTransform, NormalMatrixKeepsNormalsPerpendicularToTheSurface) {
  WorldTransform rotation = turned_spaced_and_shifted();
  const Matrix3d r = rotation.normal_matrix();
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[i][a], rotation.axes[a][i], 1e-15);

  WorldTransform sheared;
  sheared.axes = {{{1, 0, 0}, {0.6, 0.8, 0}, {0.2, -0.3, 0.9}}};
  sheared.check("sheared axes");
  const Matrix3d m = sheared.normal_matrix();
  const glm::vec3 normals[] = {{0, 0, 1}, {0.6f, 0.0f, 0.8f}, {-0.48f, 0.6f, 0.64f}};
  for (const glm::vec3& n : normals) {
    const glm::vec3 w = world_normal(m, n);
    EXPECT_NEAR(std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z), 1.0, 1e-6);
    // Two tangents of the voxel-frame surface, taken into the world by the axes.
    const glm::vec3 helper = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 t1 = glm::cross(n, helper), t2 = glm::cross(n, t1);
    for (const glm::vec3& t : {t1, t2}) {
      glm::vec3 world_t(0.0f);
      for (int a = 0; a < 3; ++a)
        for (int i = 0; i < 3; ++i) world_t[i] += static_cast<float>(sheared.axes[a][i]) * t[a];
      EXPECT_NEAR(glm::dot(w, world_t), 0.0, 1e-6);
    }
    EXPECT_GT(glm::dot(w, n), 0.0f) << "a shear without mirror keeps the outward side";
  }
}

TEST(WorldTransform, WrittenNormalsTurnWithTheAxesIncludingAMirror) {
  ScratchDirectory dir;
  const sim::Grid grid = {25, 21, 15};
  const double spacing[3] = {1.0, 1.0, 2.0};  // anisotropic, as CThead
  VolumeInfo volume;
  volume.width = grid.width;
  volume.height = grid.height;
  volume.depth = grid.depth;
  NormalWindow window(volume, {1.0, 1.0, 2.0}, "sphere");
  PlyWriterOptions plain_options, turned_options;
  plain_options.transform.spacing = {1.0, 1.0, 2.0};
  plain_options.normals = &window.normals();
  turned_options = plain_options;
  // Columns run along world -z, rows along world +x, slices along world +y: det = -1, a mirror.
  turned_options.transform.axes = {{{0, 0, -1}, {1, 0, 0}, {0, 1, 0}}};
  ASSERT_TRUE(turned_options.transform.mirrors());
  PlyWriter plain(dir / "plain.ply", plain_options);
  PlyWriter turned(dir / "turned.ply", turned_options);
  stream_phantom("sphere", grid, {&plain, &turned}, &window, spacing);
  plain.finish();
  turned.finish();
  const PlyMesh a = read_ply(dir / "plain.ply");
  const PlyMesh b = read_ply(dir / "turned.ply");
  ASSERT_EQ(a.normals.size(), a.vertex_count());
  ASSERT_EQ(b.normals.size(), a.normals.size());
  for (std::size_t i = 0; i < a.normals.size(); ++i) {
    const auto& n = a.normals[i];
    // world = n.x * axes[0] + n.y * axes[1] + n.z * axes[2]
    const std::array<float, 3> expected = {n[1], n[2], -n[0]};
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(b.normals[i][k], expected[k], 1e-6) << "vertex " << i;
  }
  // And they point out of the mirrored mesh: against each vertex's area-weighted face normal.
  std::vector<std::array<double, 3>> face_sum(b.vertex_count(), {0, 0, 0});
  for (std::size_t f = 0; f < b.face_count(); ++f) {
    const std::uint32_t begin = b.face_offsets[f], n = b.face_offsets[f + 1] - begin;
    const auto& p0 = b.positions[b.face_indices[begin]];
    for (std::uint32_t k = 1; k + 1 < n; ++k) {
      const auto& p1 = b.positions[b.face_indices[begin + k]];
      const auto& p2 = b.positions[b.face_indices[begin + k + 1]];
      const double u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
      const double v[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
      const double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                           u[0] * v[1] - u[1] * v[0]};
      for (std::uint32_t j = 0; j < n; ++j)
        for (int d = 0; d < 3; ++d) face_sum[b.face_indices[begin + j]][d] += c[d];
    }
  }
  std::size_t outward = 0;
  for (std::size_t i = 0; i < b.vertex_count(); ++i) {
    const auto& s = face_sum[i];
    outward += s[0] * b.normals[i][0] + s[1] * b.normals[i][1] + s[2] * b.normals[i][2] > 0;
  }
  EXPECT_EQ(outward, b.vertex_count());
}

TEST(WorldTransform, ValuesThatCannotPlaceAMeshAreRefusedBeforeAnyFile) {
  ScratchDirectory dir;
  const double kNan = std::numeric_limits<double>::quiet_NaN();
  const double kInf = std::numeric_limits<double>::infinity();
  std::vector<WorldTransform> bad(8);
  bad[0].spacing[0] = 0;
  bad[1].spacing[1] = -1;  // mirroring is the axes' business
  bad[2].spacing[2] = kNan;
  bad[3].origin[0] = kInf;
  bad[4].axes[1][2] = kNan;
  bad[5].axes[2] = {0, 0, 0};
  bad[6].axes[2] = {1, 1, 0};  // in the plane of the x and y axes
  bad[7].axes = {{{1, 0, 0}, {1, 1e-9, 0}, {0, 0, 1}}};
  for (std::size_t i = 0; i < bad.size(); ++i) {
    MeshWriterOptions options;
    options.transform = bad[i];
    for (MeshFormat format : {MeshFormat::ply, MeshFormat::stl, MeshFormat::obj})
      EXPECT_THROW(open_mesh_writer(dir / "mesh", format, options), Error) << "case " << i;
  }
  EXPECT_EQ(dir.listing(), "");
}

}  // namespace
}  // namespace mvox
