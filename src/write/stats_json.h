#pragma once
// The --stats report: what was extracted, how much, how fast, in how much memory, as JSON.
#include <cstdint>
#include <optional>
#include <string>

#include "mvox/slice_source.h"
#include "mvox/zbuffer_renderer.h"
#include "pipeline/memory_plan.h"
#include "pipeline/pipeline.h"
#include "labels/piece_filter.h"
#include "postprocess/layer_decimation.h"

namespace mvox {

struct RunReport {
  std::string input;                // as the user gave it
  std::string output;               // mesh file, or empty
  std::string format;               // the mesh format's --format name ("ply", "stl", ...), or empty
  std::uint64_t faces_written = 0;  // polygons, or triangles after triangulation (STL)
  std::string image;                // picture file, or empty
  RenderCounters render;            // what the renderer drew (zero without a picture)
  VolumeInfo volume;
  double threshold = 0;
  std::string method;   // "voxels" or "cubes"
  std::string engine;   // "fast" or "literal"
  std::string surface;  // "merge-rules" or "paper-table1"
  // Vertices at the interpolated crossing (--method cubes, --interpolate).
  bool interpolated = false;
  std::uint32_t smooth_iterations = 0;          // --smooth N
  std::optional<DecimationOptions> decimation;  // --decimate, --max-error
  std::optional<PieceRule> piece_rule;          // --largest, --min-faces
  PieceCounts pieces;                           // and what they kept
  PipelineResult result;
  std::uint64_t start_memory_bytes = 0;  // resident when the job started (libraries loaded)
  std::uint64_t peak_memory_bytes = 0;   // peak resident over the process's life
  MemoryPlan memory_plan;                // what the run was planned to take
  MemoryBudget memory_budget;            // and the budget it was checked against
};

std::string run_report_json(const RunReport& report);

// `text` as a JSON string literal, quotes included, always valid JSON (RFC 8259): well-formed
// UTF-8 passes as it is, control characters (and DEL) are written \u00XX, and each byte that is
// not part of well-formed UTF-8 becomes U+FFFD, the replacement character.
std::string json_string(const std::string& text);

}  // namespace mvox
