#pragma once
// mvox extract --labels: one closed surface per label of a label map (a segmentation), each
// label's inner voxels being those equal to it, in one pass over the volume.
//
// Streaming: each label present in the current slice or the one before has an engine of its own,
// fed that label's mask of each slice (1 where the sample is the label); an engine starts when
// its label appears (Engine::begin_slab after an empty slice, so its z coordinates are the
// volume's) and finishes, closing the surface, after the first slice without it. Their output
// goes to one scratch file (label_spool.h), and at the end each label's mesh file is written
// from it, one at a time. Memory: an engine workspace and a mask per label present in two
// consecutive slices, one write buffer, and the spool's record offsets (8 bytes per batch of
// output); disk: the spool, about the size of the meshes.
#include <cstdint>
#include <string>
#include <vector>

#include "labels/label_values.h"
#include "labels/piece_filter.h"
#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

struct LabelJob {
  std::string input_label;  // the input as the user named it
  std::vector<std::string> input_files;
  LabelChoice labels;
  EngineOptions engine;
  // The mesh files: the pattern's "{label}" becomes each label's number.
  std::string output_pattern;
  MeshFormat format = MeshFormat::ply;
  MeshWriterOptions mesh;  // placement, comments (the label is added to them), --triangulate
  std::string stats_path;  // empty: no report
  bool sync = false;
  bool quiet = false;
  PieceRule pieces;  // --largest, --min-faces: per label
};

struct LabelSurface {
  std::uint32_t label = 0;
  std::string file;
  std::uint64_t vertices = 0;
  std::uint64_t polygons = 0;
  std::uint64_t faces_written = 0;  // triangles for STL and --triangulate
  std::uint64_t sessions = 0;       // engines: 1 + the times it came back after an empty slice
  PieceCounts pieces;               // with --largest or --min-faces
};

struct LabelReport {
  std::string input;
  VolumeInfo volume;
  std::vector<LabelSurface> surfaces;  // by label, increasing
  std::vector<std::uint32_t> dropped;  // labels whose every piece --min-faces dropped: no file
  bool pieces = false;                 // --largest or --min-faces was asked for
  std::uint32_t most_engines = 0;      // engines running at once, at most
  std::uint64_t engine_bytes = 0;      // the workspace and mask of one engine
  std::uint64_t spool_bytes = 0;       // the scratch file on disk
  std::uint64_t spool_index_bytes = 0;
  double read_s = 0, extract_s = 0, write_s = 0, total_s = 0;
  std::uint64_t start_memory_bytes = 0;
  std::uint64_t peak_memory_bytes = 0;
};

// The file of `label` from `pattern`: every "{label}" replaced by its number.
std::string label_file_name(const std::string& pattern, std::uint32_t label);

// Runs the job; throws mvox::Error naming the input or a file. No file appears unless every
// label's mesh (and the report) was written: they appear together at the end.
LabelReport run_label_job(SliceSource& source, const LabelJob& job);

// The --stats report of a label run, as JSON.
std::string label_report_json(const LabelReport& report);

}  // namespace mvox
