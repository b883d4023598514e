#include "cli_options.h"

#include <cmath>
#include <cstdlib>

namespace mvox {

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return "'" + text + "' is not a number";
        if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
        return {};
      },
      "NUMBER");
}

void add_engine_options(CLI::App& command, EngineChoice& choice) {
  command.add_option("--method", choice.method, "Surface method")
      ->check(CLI::IsMember({"voxels"}))
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
}

EngineOptions EngineChoice::options() const {
  EngineOptions result;
  result.kind = engine == "literal" ? EngineKind::literal : EngineKind::fast;
  result.rule = surface == "paper-table1" ? SurfaceRule::paper_table1 : SurfaceRule::merge_rules;
  return result;
}

void add_ply_options(CLI::App& command, PlyChoice& choice) {
  command.add_flag("--ascii", choice.ascii, "Write ASCII PLY instead of binary little-endian");
  command
      .add_option(
          "--spacing", choice.spacing,
          "Voxel size along x,y,z, e.g. 1,1,2 for CThead (default: from the input, else 1,1,1)")
      ->delimiter(',')
      ->expected(3)
      ->check(CLI::PositiveNumber);
}

PlyWriterOptions ply_writer_options(const PlyChoice& choice, const double input_spacing[3],
                                    const double input_origin[3], const std::string& comment) {
  PlyWriterOptions options;
  options.format = choice.ascii ? PlyFormat::ascii : PlyFormat::binary_little_endian;
  for (int axis = 0; axis < 3; ++axis) {
    options.spacing[axis] = choice.spacing.empty() ? input_spacing[axis] : choice.spacing[axis];
    options.origin[axis] = input_origin[axis];
  }
  options.comments.push_back(comment);
  return options;
}

}  // namespace mvox
