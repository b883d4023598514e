#pragma once
// Command-line options shared by several subcommands: engine choice, surface rule, mesh format
// and placement, picture.
#include <CLI/CLI.hpp>
#include <array>
#include <string>

#include "cli/option_validators.h"
#include "mvox/engine.h"
#include "picture/surface_picture.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

struct EngineChoice {
  std::string method = "voxels";
  std::string engine = "fast";
  std::string surface = "merge-rules";
  bool interpolate = false;
  EngineOptions options() const;
};

// --method, --engine, --surface, --interpolate.
void add_engine_options(CLI::App& command, EngineChoice& choice);

// --format, --ascii, --triangulate, --spacing X,Y,Z and --origin X,Y,Z (both override what the
// input says).
struct MeshChoice {
  std::string format;  // empty: from the output's extension
  bool ascii = false;
  bool triangulate = false;
  std::vector<double> spacing;  // empty: from the input (1,1,1 for images and raw data)
  std::vector<double> origin;   // empty: from the input (0,0,0 for images and raw data)

  // The format to write `output` in: --format, else the extension (.ply, .stl, .obj, any case),
  // else binary PLY for standard output ("-"); --ascii makes PLY ASCII. Throws
  // CLI::ValidationError (a usage error) for an extension that names no format, --ascii with
  // STL, or --format without an output.
  MeshFormat format_for(const std::string& output) const;
};
void add_mesh_options(CLI::App& command, MeshChoice& choice);

// The mesh writer options for a run: the input's placement (spacing, origin, axes) unless
// --spacing or --origin was given, --triangulate, and `comment`. The placement is checked now,
// for pictures too, since the mesh and the report give it in float: a value out of range
// (WorldTransform::check) is an mvox::Error naming `input_label`, the options' own values having
// been checked when parsed; a volume whose vertices would pass float's range
// (WorldTransform::reach_problem) is a usage error naming --spacing and --origin when either
// was given, else an mvox::Error naming `input_label`.
MeshWriterOptions mesh_writer_options(const MeshChoice& choice, const VolumeInfo& input,
                                      const std::string& input_label, const std::string& comment);

// The picture options: --image, --size, --view, --perspective, --fov, --flat, --cut, and for
// extraction also --frames, --every and --show.
struct PictureChoice {
  std::string image;
  std::string size = "512x512";
  std::vector<float> view;  // azimuth, elevation[, roll] in degrees
  bool perspective = false;
  float field_of_view_deg = 30;
  bool flat = false;
  float cut = 0;  // the cutaway, a fraction of the depth along the view (0: none)
  std::string frames_dir;
  std::uint32_t every = 10;
  bool show = false;
  // Throws mvox::Error for a malformed --size.
  PictureOptions options() const;
  // Any picture at all: --image, --frames or --show.
  bool wanted_any() const { return !image.empty() || !frames_dir.empty() || show; }
};
enum class PictureUse { extraction, mesh_file };
void add_picture_options(CLI::App& command, PictureChoice& choice, PictureUse use);

}  // namespace mvox
