#include "cli/cli_options.h"

#include <filesystem>
#include <optional>
#include <system_error>

#include "error.h"
#include "write/standard_descriptors.h"

namespace mvox {
namespace {

bool is_existing_non_regular_file(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  return !error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
         !std::filesystem::is_directory(status);
}

// "WxH" or "N" (NxN), decimal digits only, 1 to kMaxImageSide per side. Strict: sscanf's %u
// would read "1e3" as 1, skip blanks and signs, and wrap "4294967808" around to 512.
bool parse_picture_size(const std::string& text, unsigned* width, unsigned* height) {
  const std::size_t x = text.find('x');
  std::uint64_t w = 0, h = 0;
  if (!parse_whole_number(text.substr(0, x), kMaxImageSide, &w)) return false;
  if (x == std::string::npos)
    h = w;
  else if (!parse_whole_number(text.substr(x + 1), kMaxImageSide, &h))
    return false;
  if (w == 0 || h == 0) return false;
  *width = static_cast<unsigned>(w);
  *height = static_cast<unsigned>(h);
  return true;
}

std::string picture_size_problem(const std::string& text) {
  return "'" + text + "' is not a picture size: give WxH or N, 1 to " +
         std::to_string(kMaxImageSide) + " pixels per side";
}

}  // namespace

void add_engine_options(CLI::App& command, EngineChoice& choice) {
  command
      .add_option("--method", choice.method,
                  "voxels: marching voxels (polygons, closed surface); cubes: classic marching "
                  "cubes (triangles, interpolated vertices; the paper's baseline)")
      ->check(CLI::IsMember({"voxels", "cubes"}))
      ->capture_default_str();
  command
      .add_option("--engine", choice.engine,
                  "fast: per-cube table; literal: the paper's merge passes voxel by voxel "
                  "(same output, slower, for checking)")
      ->check(CLI::IsMember({"fast", "literal"}))
      ->capture_default_str();
  command
      .add_option("--surface", choice.surface,
                  "merge-rules: closed and hole-free; paper-table1: the paper's Table 1 for five "
                  "and six inner voxels, which opens holes (to reproduce the paper)")
      ->check(CLI::IsMember({"merge-rules", "paper-table1"}))
      ->capture_default_str();
  command.add_flag("--interpolate", choice.interpolate,
                   "Move each vertex along its voxel edge from the midpoint to where the "
                   "interpolated samples cross the threshold (smooth, as marching cubes places "
                   "them); the same polygons, still closed. Marching cubes always does");
}

EngineOptions EngineChoice::options() const {
  EngineOptions result;
  if (method == "cubes") {
    if (engine != "fast" || surface != "merge-rules")
      throw UsageError(
          "--method cubes",
          "has its own table; --engine and --surface choose how marching voxels works");
    result.method = SurfaceMethod::cubes;
    return result;
  }
  result.kind = engine == "literal" ? EngineKind::literal : EngineKind::fast;
  result.rule = surface == "paper-table1" ? SurfaceRule::paper_table1 : SurfaceRule::merge_rules;
  result.interpolate = interpolate;
  return result;
}

void add_mesh_options(CLI::App& command, MeshChoice& choice) {
  command
      .add_option("--format", choice.format,
                  std::string("Mesh format: ") + kMeshFormatChoices +
                      " (default: from the output's extension .ply, .stl or .obj; binary PLY "
                      "for '-o -')")
      ->check(CLI::IsMember({"ply", "ply-ascii", "stl", "obj"}));
  command.add_flag("--ascii", choice.ascii, "Write ASCII PLY instead of binary little-endian");
  command.add_flag("--triangulate", choice.triangulate,
                   "Split every polygon into triangles, none lying in a cube face (STL always "
                   "does)");
  command
      .add_option(
          "--spacing", choice.spacing,
          "Voxel size along x,y,z, e.g. 1,1,2 for CThead (default: from the input, else 1,1,1)")
      ->delimiter(',')
      ->expected(3)
      ->check(spacing_number());
  command
      .add_option("--origin", choice.origin,
                  "Position of voxel (0,0,0) along x,y,z, in the units of the spacing (default: "
                  "from the input, else 0,0,0)")
      ->delimiter(',')
      ->expected(3)
      ->check(origin_number());
}

MeshFormat MeshChoice::format_for(const std::string& output) const {
  if (output.empty()) {
    if (!format.empty()) throw CLI::ValidationError("--format", "needs a mesh output (-o)");
    return MeshFormat::ply;  // no mesh is written
  }
  std::optional<MeshFormat> chosen = mesh_format_named(format);
  if (!chosen) chosen = mesh_format_of_path(output);
  // Standard output, devices and pipes (/dev/null, a FIFO) have no extension to go by: like
  // "-", they get the native format.
  if (!chosen &&
      (output == "-" || descriptor_named_by(output) || is_existing_non_regular_file(output)))
    chosen = MeshFormat::ply;
  // An existing directory is not a place for a mesh whatever its name: say that (exit 1, when
  // the file cannot be created) rather than ask for an extension.
  std::error_code error;
  if (!chosen && std::filesystem::is_directory(output, error)) chosen = MeshFormat::ply;
  if (!chosen)
    throw CLI::ValidationError("--output", "'" + output +
                                               "' does not end in .ply, .stl or .obj; use one "
                                               "of these or give --format " +
                                               kMeshFormatChoices);
  if (ascii) {
    if (*chosen == MeshFormat::stl)
      throw CLI::ValidationError("--ascii", "STL is written in binary only; use PLY or OBJ");
    if (*chosen == MeshFormat::ply) chosen = MeshFormat::ply_ascii;
    // OBJ is text already.
  }
  return *chosen;
}

MeshWriterOptions mesh_writer_options(const MeshChoice& choice, const VolumeInfo& input,
                                      const std::string& input_label, const std::string& comment) {
  MeshWriterOptions options;
  options.transform = WorldTransform::of_volume(input);
  if (!choice.spacing.empty())
    for (int axis = 0; axis < 3; ++axis) options.transform.spacing[axis] = choice.spacing[axis];
  if (!choice.origin.empty())
    for (int axis = 0; axis < 3; ++axis) options.transform.origin[axis] = choice.origin[axis];
  options.transform.check(input_label);
  const std::string reach = options.transform.reach_problem(input.width, input.height, input.depth);
  if (!reach.empty()) {
    std::string options_given;
    if (!choice.spacing.empty()) options_given = "--spacing";
    if (!choice.origin.empty())
      options_given += options_given.empty() ? "--origin" : " and --origin";
    if (!options_given.empty()) throw CLI::ValidationError(options_given, reach);
    throw Error(input_label, reach);
  }
  options.triangulate = choice.triangulate;
  options.comments.push_back(comment);
  return options;
}

void add_picture_options(CLI::App& command, PictureChoice& choice, PictureUse use) {
  const bool extraction = use == PictureUse::extraction;
  command.add_option("--image", choice.image,
                     extraction ? "Also render the surface into this picture (.png, .pgm, .tif)"
                                : "The picture to write (.png, .pgm, .tif); same as -o");
  command.add_option("--image-size", choice.size, "Picture size in pixels, WxH or N for NxN")
      ->capture_default_str()
      // Checked while parsing: a malformed size is a usage error (exit 2).
      ->check(CLI::Validator(
          [](std::string& text) {
            unsigned width = 0, height = 0;
            return parse_picture_size(text, &width, &height) ? std::string()
                                                             : picture_size_problem(text);
          },
          "WxH"));
  command
      .add_option("--view", choice.view,
                  "View direction in degrees: AZIMUTH,ELEVATION[,ROLL]. 0,0 looks from the top "
                  "rows of the slices (the front, for CT and MR) with later slices up; azimuth "
                  "turns the camera towards +x, elevation lifts it, roll turns the picture")
      ->delimiter(',')
      ->expected(2, 3)
      ->check(number_from(-360, 360));
  command.add_flag("--perspective", choice.perspective,
                   "Perspective projection (default: orthographic, the volume fitted)");
  command.add_option("--fov", choice.field_of_view_deg, "Perspective field of view in degrees")
      ->check(number_from(1, 170))
      ->capture_default_str();
  command.add_flag("--flat", choice.flat,
                   "Shade each polygon flat instead of with smooth gradient normals");
  command
      .add_option("--cut", choice.cut,
                  extraction
                      ? "Cutaway: cut away the nearest FRACTION of the volume's depth along the "
                        "view (0.5: through the centre) to show what lies inside; where the "
                        "plane cuts through the surface it is capped in flat grey. 0: no cut"
                      : "Cutaway: cut away the nearest FRACTION of the mesh's depth along the view "
                        "(0.5: through the centre); with --cull, where the plane cuts through the "
                        "(closed) surface it is capped in flat grey. 0: no cut")
      ->check(number_from(0, 1));
  if (!extraction) return;
  command.add_option("--frames", choice.frames_dir,
                     "Also write the picture so far into this directory every --every slices "
                     "(frame_0010.png, ...; created if missing)");
  command.add_option("--every", choice.every, "Slices between frames")
      ->transform(whole_number_from(1, 1u << 30))
      ->capture_default_str();
  command.add_flag("--show", choice.show, "Show the picture growing in a window (needs a display)");
}

PictureOptions PictureChoice::options() const {
  PictureOptions result;
  result.image_path = image;
  unsigned width = 0, height = 0;
  if (!parse_picture_size(size, &width, &height))
    throw Error("--image-size", picture_size_problem(size));
  result.width = width;
  result.height = height;
  if (view.size() >= 2) {
    result.view.azimuth_deg = view[0];
    result.view.elevation_deg = view[1];
  }
  if (view.size() == 3) result.view.roll_deg = view[2];
  result.view.perspective = perspective;
  result.view.field_of_view_deg = field_of_view_deg;
  result.view.cut = cut;
  result.smooth = !flat;
  result.frames_dir = frames_dir;
  result.every = every;
  result.show = show;
  return result;
}

}  // namespace mvox
