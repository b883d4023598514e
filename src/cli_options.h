#pragma once
// Command-line options shared by several subcommands: engine choice, surface rule, spacing.
#include <CLI/CLI.hpp>
#include <array>
#include <string>

#include "mvox/engine.h"
#include "ply_writer.h"

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

// --ascii and --spacing X,Y,Z (the spacing overrides what the input says).
struct PlyChoice {
  bool ascii = false;
  std::vector<double> spacing;  // empty: from the input (1,1,1 for images and raw data)
};
void add_ply_options(CLI::App& command, PlyChoice& choice);

// The PLY options for a run, with the input's own spacing unless --spacing was given.
PlyWriterOptions ply_writer_options(const PlyChoice& choice, const double input_spacing[3],
                                    const double input_origin[3], const std::string& comment);

}  // namespace mvox
