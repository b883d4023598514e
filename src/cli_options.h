#pragma once
// Command-line options shared by several subcommands: engine choice, surface rule, spacing.
#include <CLI/CLI.hpp>
#include <array>
#include <string>

#include "mvox/engine.h"
#include "ply_writer.h"
#include "surface_picture.h"

namespace mvox {

struct EngineChoice {
  std::string method = "voxels";
  std::string engine = "fast";
  std::string surface = "merge-rules";
  EngineOptions options() const;
};

// Accepts a finite number (refuses nan and inf), for thresholds.
CLI::Validator finite_number();

// --method, --engine, --surface.
void add_engine_options(CLI::App& command, EngineChoice& choice);

// --ascii, --spacing X,Y,Z and --origin X,Y,Z (both override what the input says).
struct PlyChoice {
  bool ascii = false;
  std::vector<double> spacing;  // empty: from the input (1,1,1 for images and raw data)
  std::vector<double> origin;   // empty: from the input (0,0,0 for images and raw data)
};
void add_ply_options(CLI::App& command, PlyChoice& choice);

// The PLY options for a run, with the input's own spacing and origin unless --spacing or
// --origin was given.
PlyWriterOptions ply_writer_options(const PlyChoice& choice, const double input_spacing[3],
                                    const double input_origin[3], const std::string& comment);

// The picture options: --image, --size, --view, --perspective, --fov, --flat, and for
// extraction also --frames, --every and --show.
struct PictureChoice {
  std::string image;
  std::string size = "512x512";
  std::vector<float> view;  // azimuth, elevation[, roll] in degrees
  bool perspective = false;
  float field_of_view_deg = 30;
  bool flat = false;
  std::string frames_dir;
  std::uint32_t every = 10;
  bool show = false;
  // Throws mvox::Error for a malformed --size.
  PictureOptions options() const;
};
enum class PictureUse { extraction, mesh_file };
void add_picture_options(CLI::App& command, PictureChoice& choice, PictureUse use);

}  // namespace mvox
