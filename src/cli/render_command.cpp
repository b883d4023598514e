// mvox render MESH.ply -o picture.png: an existing mesh through the same renderer as
// `mvox extract --image`, to compare files and methods or to check a file by eye.
#include <cstdio>
#include <memory>

#include "cli/cli_options.h"
#include "cli/commands.h"
#include "error.h"
#include "message_line.h"
#include "picture/mesh_render.h"
#include "picture/picture_frame.h"
#include "pipeline/mesh_job.h"
#include "pipeline/termination.h"
#include "read/ply/ply_reader.h"
#include "write/output_file.h"
#include "write/output_targets.h"
#include "write/slice_image_writer.h"

namespace mvox {
namespace {

struct RenderArguments {
  std::string mesh;
  std::string output;
  bool cull = false;
  bool quiet = false;
  PictureChoice picture;
};

void run_render(const RenderArguments& args) {
  PictureChoice choice = args.picture;
  if (args.output.empty() == choice.image.empty())
    throw UsageError("mvox render", args.output.empty()
                                        ? "name the picture with -o picture.png"
                                        : "give the picture once, with -o or --image");
  if (choice.image.empty()) choice.image = args.output;
  const PictureOptions options = choice.options();
  check_image_extension(options.image_path);
  check_output_targets(
      {{options.image_path, args.output.empty() ? "--image" : "-o", "the picture"}}, std::nullopt,
      {args.mesh}, InputFiles::not_yet_opened);
  OutputFile file(options.image_path);  // fails now, not after reading a large mesh

  set_interrupt_subject(args.mesh);  // memory running out names the mesh
  PlyMesh mesh = read_ply(args.mesh);
  glm::vec3 box_min, box_max;
  if (!face_bounds(mesh, &box_min, &box_max)) throw Error(args.mesh, "no faces to render");
  std::vector<std::array<float, 3>> normals;
  if (options.smooth) normals = mesh.normals.empty() ? area_weighted_normals(mesh) : mesh.normals;
  // Drawn in the frame of its box, computed in double (picture_frame.h): a mesh near 1e-44 or
  // 3e38 has a float box the camera cannot fit. The positions are moved in place, after the
  // normals, which need the file's own.
  const auto to_double = [](const glm::vec3& v) { return Vector3d{v.x, v.y, v.z}; };
  const PictureFrame frame = PictureFrame::around(to_double(box_min), to_double(box_max));
  for (std::array<float, 3>& p : mesh.positions) {
    const glm::vec3 placed = frame.point({p[0], p[1], p[2]});
    p = {placed.x, placed.y, placed.z};
  }
  box_min = frame.point(to_double(box_min));
  box_max = frame.point(to_double(box_max));

  Lighting lighting = options.lighting;
  // Any mesh may come here, open or inconsistently wound: draw both sides unless told it is
  // closed and wound outwards (as mvox's are), which halves the work.
  lighting.cull_back_faces = args.cull;
  std::vector<float> memory(zbuffer_workspace_bytes(options.width, options.height) / sizeof(float) +
                            1);
  ZBufferRenderer renderer;
  const Camera camera = fit_camera(box_min, box_max, options.view, options.width, options.height);
  const Status status =
      renderer.init(memory.data(), memory.size() * sizeof(float), camera, lighting);
  if (status != Status::ok)
    throw Error("renderer", std::string("cannot start: ") + status_message(status));
  draw_mesh(mesh, normals, renderer);

  const std::vector<unsigned char> encoded =
      encode_slice_image(options.image_path, renderer.picture());
  file.write(encoded.data(), encoded.size());
  file.commit();
  if (!args.quiet)
    std::fprintf(stderr, "%s: %s faces of %s (%s normals), %ux%u, %s triangles drawn\n",
                 one_line(options.image_path).c_str(), grouped(mesh.face_count()).c_str(),
                 one_line(args.mesh).c_str(),
                 !options.smooth        ? "flat"
                 : mesh.normals.empty() ? "area-weighted"
                                        : "the file's",
                 options.width, options.height,
                 grouped(renderer.counters().triangles_drawn).c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArguments>();
  CLI::App* command = app.add_subcommand(
      "render", "Render a PLY mesh into a shaded picture with the same renderer as extract");
  command->add_option("MESH", args->mesh, "PLY file (ASCII or binary)")->required();
  command->add_option("-o,--output", args->output, "Picture file (.png, .pgm, .tif, .bmp, .jpg)");
  add_picture_options(*command, args->picture, PictureUse::mesh_file);
  command->add_flag("--cull", args->cull,
                    "Skip faces seen from behind: faster, and exact for closed meshes wound "
                    "outwards (mvox's own)");
  command->add_flag("-q,--quiet", args->quiet, "No summary line");
  command->callback([args] { run_render(*args); });
}

}  // namespace mvox
