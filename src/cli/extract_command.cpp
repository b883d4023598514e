// mvox extract INPUT... -t D -o mesh.ply|.stl|.obj: the main job.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include "cli/cli_options.h"
#include "cli/commands.h"
#include "error.h"
#include "labels/label_job.h"
#include "labels/tissue_presets.h"
#include "labels/value_range_source.h"
#include "message_line.h"
#include "pipeline/memory_plan.h"
#include "pipeline/mesh_job.h"
#include "pipeline/termination.h"
#include "postprocess/layer_decimation.h"
#include "read/dicom/dicom_series_source.h"
#include "read/input_files.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"
#include "write/buffered_writer.h"

namespace mvox {
namespace {

struct ExtractArguments {
  std::vector<std::string> inputs;
  std::string raw_spec;
  DicomChoice dicom;
  double threshold = 0;
  std::string output;
  std::string stats_path;
  bool quiet = false;
  EngineChoice engine;
  MeshChoice mesh;
  bool normals = false;
  std::uint32_t smooth = 0;
  double decimate = 0;   // 0: not given
  double max_error = 0;  // 0: not given
  PictureChoice picture;
  std::string max_memory;  // as given; empty: the default budget
  bool dry_run = false;
  bool sync = false;
  unsigned threads = 0;  // 0: not given (chosen by the volume's size)
  std::uint32_t slab_slices = 0;
  std::string labels;       // --labels LIST ("" with the option alone: every label)
  PieceRule pieces;         // --largest, --min-faces
  std::string tissue;       // --tissue NAME (labels/tissue_presets.h); empty: not given
  bool hounsfield = false;  // --hu: the input's values are Hounsfield units
  const CLI::Option* labels_option = nullptr;
  const CLI::Option* threshold_option = nullptr;
};

// A threshold beyond what the samples can hold makes no voxel inner, or every voxel: an empty
// file or a box, after a full run. Refused before reading, naming the input and its type.
void check_threshold_range(const std::string& input, SampleType type, double threshold) {
  double lowest = 0, highest = 0;
  switch (type) {
    case SampleType::u8: highest = 255; break;
    case SampleType::u16: highest = 65535; break;
    case SampleType::i16: lowest = -32768, highest = 32767; break;
    case SampleType::f32: return;  // any finite threshold can split float samples
  }
  char problem[160];
  if (threshold > highest)
    std::snprintf(problem, sizeof problem,
                  "threshold %g is above the largest %s sample (%g): no voxel would be inner",
                  threshold, sample_type_name(type), highest);
  else if (threshold <= lowest)
    std::snprintf(problem, sizeof problem,
                  "threshold %g is not above the smallest %s sample (%g): every voxel would be "
                  "inner",
                  threshold, sample_type_name(type), lowest);
  else
    return;
  throw Error(input, problem);
}

// The options --labels cannot take, as usage errors before anything is read.
void check_label_options(const ExtractArguments& args) {
  if (args.threshold_option->count() > 0)
    throw CLI::ValidationError("--labels",
                               "a voxel belongs to label L when its value is L: "
                               "leave -t out");
  const std::string& pattern = args.output;
  if (pattern.find("{label}") == std::string::npos ||
      std::filesystem::path(pattern).parent_path().string().find("{label}") != std::string::npos)
    throw CLI::ValidationError("--labels",
                               "one mesh per label: give -o with {label} in the "
                               "file name, e.g. -o 'organ_{label}.stl'");
  const std::pair<bool, const char*> refused[] = {
      {!args.picture.image.empty(), "--image"},
      {!args.picture.frames_dir.empty(), "--frames"},
      {args.picture.show, "--show"},
      {args.normals, "--normals"},
      {args.smooth > 0, "--smooth"},
      {args.decimate > 0, "--decimate"},
      {args.max_error > 0, "--max-error"},
      {args.threads > 1, "--threads"},
      {args.dry_run, "--dry-run"},
      {!args.max_memory.empty(), "--max-memory"},
  };
  for (const auto& [given, option] : refused)
    if (given)
      throw CLI::ValidationError(option,
                                 "not with --labels, which writes each label's mesh on "
                                 "one thread, without pictures or post-processing");
  const EngineOptions engine = args.engine.options();
  if (engine.method != SurfaceMethod::voxels || engine.interpolate)
    throw CLI::ValidationError("--labels",
                               "labels are extracted by marching voxels at their "
                               "voxel boundaries: leave out --method cubes and "
                               "--interpolate");
}

void run_labels(const ExtractArguments& args) {
  check_label_options(args);
  LabelJob job;
  if (const std::string problem = parse_label_choice(args.labels, &job.labels); !problem.empty())
    throw CLI::ValidationError("--labels", problem);
  job.format = args.mesh.format_for(args.output);
  set_interrupt_subject(inputs_label(args.inputs));
  InputOptions input_options;
  if (!args.raw_spec.empty()) input_options.raw = parse_raw_format(args.raw_spec);
  input_options.dicom = args.dicom;
  OpenedInput input = open_input(args.inputs, input_options);
  job.input_label = inputs_label(args.inputs);
  job.input_files = std::move(input.files);
  job.engine = args.engine.options();
  job.output_pattern = args.output;
  job.mesh =
      mesh_writer_options(args.mesh, input.source->info(), job.input_label, "mvox marching voxels");
  job.stats_path = args.stats_path;
  job.sync = args.sync;
  job.quiet = args.quiet;
  job.pieces = args.pieces;
  BufferedWriter::allow_background_writes(false);  // one thread: see check_label_options
  run_label_job(*input.source, job);
}

// --tissue's thresholds are Hounsfield units: a CT DICOM series says so itself (Modality CT,
// rescale applied), any other input only when the user adds --hu.
void check_hounsfield_input(const ExtractArguments& args, const SliceSource& source) {
  const auto* dicom = dynamic_cast<const DicomSeriesSource*>(&source);
  if (args.hounsfield || (dicom && dicom->modality() == "CT")) return;
  const std::string what =
      dicom ? "is a DICOM series of modality " +
                  (dicom->modality().empty() ? std::string("unknown") : dicom->modality()) +
                  ", not CT"
            : "does not say its values are Hounsfield units";
  throw Error(inputs_label(args.inputs),
              "--tissue " + args.tissue + " is a range of Hounsfield units, and the input " + what +
                  "; add --hu if its values are HU (a CT saved as NIfTI or NRRD), or "
                  "give -t in its own units");
}

void run_extract(const ExtractArguments& args, const ExtractRunner& runner) {
  if (args.labels_option->count() > 0) {
    if (!args.tissue.empty())
      throw CLI::ValidationError("--tissue", "not with --labels, which takes each label's voxels");
    // A runner runs the job elsewhere (mvox-mpi's ranks); the label job runs on one process.
    if (runner)
      throw CLI::ValidationError("--labels", "one process extracts the labels: use mvox extract");
    return run_labels(args);
  }
  if (!args.tissue.empty() && args.threshold_option->count() > 0)
    throw CLI::ValidationError("--tissue", "give -t or --tissue, not both");
  if (args.threshold_option->count() == 0 && args.tissue.empty())
    throw CLI::RequiredError("--threshold");
  const MeshFormat format = args.mesh.format_for(args.output);  // a usage error before reading
  if (args.normals && format == MeshFormat::stl)
    throw CLI::ValidationError("--normals",
                               "STL has face normals only; write PLY or OBJ for vertex normals");
  // An interrupt while the input is opened (a FIFO waiting for its writer) names it.
  set_interrupt_subject(inputs_label(args.inputs));
  InputOptions input_options;
  if (!args.raw_spec.empty()) input_options.raw = parse_raw_format(args.raw_spec);
  // Opening reads headers (of the first slice, for image stacks): that is reading.
  const auto open_start = std::chrono::steady_clock::now();
  // Notes about the input (which DICOM series, fallbacks) wait until it has been accepted, so
  // that a refusal before the run stays one line.
  std::vector<std::string> notes;
  input_options.dicom = args.dicom;
  if (!args.quiet)
    input_options.dicom.note = [&notes](const std::string& line) { notes.push_back(line); };
  // The input-format table (read/input_format.h) picks the reader, and refuses, as usage
  // errors, options that do not fit the input (--raw with a NRRD file, --series without DICOM).
  OpenedInput input = open_input(args.inputs, input_options);
  std::unique_ptr<SliceSource>& source = input.source;
  double threshold = args.threshold;
  std::string tissue_comment;
  if (!args.tissue.empty()) {
    check_hounsfield_input(args, *source);
    const TissuePreset& preset = *find_tissue(args.tissue);  // checked while parsing
    if (preset.range()) {
      // The voxels in the range, as a 0/1 volume whose surface is at threshold 1.
      source = std::make_unique<ValueRangeSource>(std::move(input.source), preset.low, preset.high);
      threshold = 1;
      char range[96];
      std::snprintf(range, sizeof range, ", --tissue %s (%g .. %g HU)", args.tissue.c_str(),
                    preset.low, preset.high);
      tissue_comment = range;
    } else {
      threshold = preset.low;
      tissue_comment = ", --tissue " + args.tissue + " (HU)";
    }
  }
  const VolumeInfo& info = source->info();
  check_threshold_range(inputs_label(args.inputs), info.type, threshold);
  for (const std::string& line : notes) print_message("note", line);

  MeshJob job;
  job.source_open_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - open_start).count();
  job.input_label = inputs_label(args.inputs);
  job.input_files = std::move(input.files);
  job.threshold = threshold;
  job.engine = args.engine.options();
  job.output = args.output;
  job.format = format;
  job.stats_path = args.stats_path;
  job.quiet = args.quiet;
  char comment[160];
  if (job.engine.method == SurfaceMethod::cubes)
    std::snprintf(comment, sizeof comment, "mvox marching cubes, threshold %g", threshold);
  else
    std::snprintf(comment, sizeof comment, "mvox marching voxels, threshold %g, %s engine, %s%s",
                  threshold, engine_kind_name(job.engine.kind), surface_rule_name(job.engine.rule),
                  job.engine.interpolate ? ", interpolated vertices" : "");
  std::string described = comment + tissue_comment;
  if (args.smooth > 0) described += ", smoothed " + std::to_string(args.smooth) + " times";
  job.mesh = mesh_writer_options(args.mesh, info, job.input_label, described);
  job.normals = args.normals;
  job.smooth_iterations = args.smooth;
  if (args.decimate > 0 || args.max_error > 0) {
    if (!decimation_available())
      throw Error(args.decimate > 0 ? "--decimate" : "--max-error",
                  "this mvox was built without meshoptimizer: install it (apt-get install "
                  "libmeshoptimizer-dev) and build again");
    if (args.normals)
      throw CLI::ValidationError("--normals",
                                 "not with --decimate or --max-error: a vertex may leave long "
                                 "after the slices its gradient needs");
    DecimationOptions decimation;
    decimation.ratio = args.decimate > 0 ? args.decimate : 1.0;
    decimation.max_error_voxels = args.max_error;
    job.decimation = decimation;
  }
  if (args.pieces.active()) {
    // Pieces are known only once the whole surface is: the mesh waits in a spool, so the
    // picture (drawn as slices come) and the normals (from slices long gone) cannot follow.
    const char* option = args.pieces.largest ? "--largest" : "--min-faces";
    if (args.output.empty())
      throw CLI::ValidationError(option, "keeps pieces of the mesh: give -o");
    if (args.picture.wanted_any())
      throw CLI::ValidationError(option,
                                 "not with a picture, which is drawn as the surface "
                                 "streams, before its pieces are known");
    if (args.normals)
      throw CLI::ValidationError(option,
                                 "not with --normals, whose slices are gone when the "
                                 "pieces are known");
    if (args.decimate > 0 || args.max_error > 0)
      throw CLI::ValidationError(option,
                                 "not with --decimate or --max-error, whose triangles "
                                 "come out long after their vertices");
    job.pieces = args.pieces;
  }
  job.picture = args.picture.options();
  // Decimated vertices may leave long after the slices their gradients need: pictures are flat.
  if (job.decimation) job.picture.smooth = false;
  if (args.max_memory.empty()) {
    job.budget = default_memory_budget();
  } else {
    job.budget.bytes = *parse_memory_size(args.max_memory);  // checked while parsing
    job.budget.source = "--max-memory " + args.max_memory;
  }
  job.dry_run = args.dry_run;
  job.sync = args.sync;
  job.slab_slices = args.slab_slices;
  job.threads = args.threads;  // 0: chosen by the volume's size (MeshJob::threads)
  job.read_ahead = args.threads != 1;
  BufferedWriter::allow_background_writes(args.threads != 1);
  if (runner) {
    runner(*source, job);
  } else {
    run_mesh_job(*source, job);
  }
}

}  // namespace

void add_extract_command(CLI::App& app, ExtractRunner runner) {
  auto args = std::make_shared<ExtractArguments>();
  CLI::App* command = app.add_subcommand(
      "extract",
      "Extract the surface at threshold D (inner voxels: value >= D) and write it as a mesh "
      "(PLY, STL or OBJ), a shaded picture, or both");
  command
      ->add_option("INPUT", args->inputs,
                   "Slices: a directory or glob of PNG/TIFF/JPEG/BMP/PGM images (TIFF files "
                   "may hold many pages), a DICOM series (a directory or files; recognised by "
                   "content), one NRRD (.nrrd, .nhdr), MetaImage (.mhd, .mha) or NIfTI (.nii, "
                   ".nii.gz, .hdr) volume, raw "
                   "slice files, or one raw volume file (with --raw); '-' for standard input "
                   "(a raw volume piped in)")
      ->transform(standard_input_dash())
      ->required();
  args->threshold_option =
      command
          ->add_option("-t,--threshold", args->threshold,
                       "Threshold D in sample units (required, but for --labels)")
          ->check(finite_number());
  args->labels_option =
      command
          ->add_option("--labels", args->labels,
                       "Label maps (segmentations): one closed surface per label, a label's "
                       "voxels being those equal to it; LIST is 1,4,7 or left out for every "
                       "positive integer in the volume. -o must hold {label}, e.g. "
                       "-o 'organ_{label}.stl'; no -t")
          ->expected(0, 1);
  command
      ->add_option("--tissue", args->tissue,
                   "CT presets in Hounsfield units instead of -t: bone (>= 300), skin (>= -300, "
                   "the body against air), fat (-190 .. -30), soft-tissue (-29 .. 150; muscle "
                   "and organs); for CT DICOM series, or any input with --hu")
      // The presets' own table, so that a preset added there is accepted here.
      ->check(CLI::Validator(
          [](std::string& name) {
            return find_tissue(name) ? std::string()
                                     : "'" + name + "' is not one of " + tissue_names();
          },
          "NAME"));
  command->add_flag("--hu", args->hounsfield,
                    "The input's values are Hounsfield units (a CT saved as NIfTI, NRRD, ...), "
                    "for --tissue");
  command->add_flag("--largest", args->pieces.largest,
                    "Keep only the largest connected piece of the surface (most faces), per "
                    "label with --labels: drops floating specks and islands");
  command
      ->add_option("--min-faces", args->pieces.min_faces,
                   "Drop connected pieces of fewer than N faces (polygons), per label with "
                   "--labels")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 62));
  command->add_option("-o,--output", args->output,
                      "Output mesh: .ply, .stl or .obj ('-' for standard output); may be left "
                      "out with --image");
  command
      ->add_option("--raw", args->raw_spec,
                   "Headerless input: WxH:TYPE for one file per slice, WxHxD:TYPE for one "
                   "volume file; TYPE is u8, u16le, u16be, i16le, i16be or f32le")
      // Checked while parsing, so that a malformed spec is a usage error (exit 2) like any
      // other malformed option value.
      ->check(CLI::Validator(
          [](std::string& spec) {
            try {
              parse_raw_format(spec);
              return std::string();
            } catch (const Error& e) {
              return e.problem();
            }
          },
          "WxH[xD]:TYPE"));
  command->add_flag("--dicom", args->dicom.force,
                    "Read INPUT as DICOM even without the DICM preamble or a .dcm name");
  command->add_option("--series", args->dicom.series_uid,
                      "DICOM: the SeriesInstanceUID to read (default: the series with the most "
                      "slices)");
  add_engine_options(*command, args->engine);
  add_mesh_options(*command, args->mesh);
  command->add_flag("--normals", args->normals,
                    "Write smooth outward normals (from the density gradient) into the mesh: "
                    "PLY nx, ny, nz or OBJ vn");
  command
      ->add_option("--smooth", args->smooth,
                   "Smooth the surface N times as it streams, each vertex held on its own voxel "
                   "edge (so it still separates the same voxels; the same polygons, still "
                   "closed); for binary masks and segmentations. About 10 is a good start. One "
                   "engine does it (no slab threads)")
      ->check(CLI::Range(0, 1000));
  command
      ->add_option("--decimate", args->decimate,
                   "Simplify the surface to about RATIO of its triangles as it streams (e.g. "
                   "0.1), closed and manifold, in bounded memory; triangles only. One engine "
                   "does it; the picture is then shaded flat and --normals is refused")
      ->check(CLI::Range(0.0, 1.0).description("RATIO in (0, 1]") &
              CLI::Validator(
                  [](std::string& text) {
                    return std::stod(text) > 0 ? std::string() : std::string("must be above 0");
                  },
                  "", "above 0"));
  command
      ->add_option("--max-error", args->max_error,
                   "With or without --decimate: let the simplification move the surface by at "
                   "most E voxels")
      ->check(CLI::PositiveNumber);
  add_picture_options(*command, args->picture, PictureUse::extraction);
  command->add_option("--stats", args->stats_path,
                      "Also write a JSON report: dimensions, counts, time per phase, peak memory");
  command
      ->add_option("--max-memory", args->max_memory,
                   "Refuse, before reading, a run that would take more memory than SIZE (e.g. "
                   "64M, 2G; 'none': no limit). Default: the physical memory (or this process's "
                   "cgroup or ulimit -v limit, if lower)")
      ->check(CLI::Validator(
          [](std::string& text) {
            const std::optional<std::uint64_t> bytes = parse_memory_size(text);
            // 0 stands for no budget inside; typed, it asked for no memory at all, and the run
            // went ahead unlimited.
            if (bytes == std::uint64_t{0} && text != "none")
              return "'" + text + "' is no memory at all: give a size, or none for no limit";
            return bytes ? std::string()
                         : "'" + text +
                               "' is not a memory size: give e.g. 512K, 64M, 2G, 1.5G, a number "
                               "of bytes, or none";
          },
          "SIZE"));
  command->add_flag("--dry-run", args->dry_run,
                    "Read the input's headers only, check the outputs and the memory budget, "
                    "print what the run would take, and stop: no slice is read, nothing written");
  command->add_flag("--sync", args->sync,
                    "Make every output durable (fsync) before it replaces its target, so that "
                    "a power loss right after cannot leave it empty; costs 5-20 ms a file");
  command
      ->add_option("--threads", args->threads,
                   "Extracting threads. Above 1, the volume is cut into slabs of slices "
                   "extracted in parallel; the mesh and the picture are what one thread makes, "
                   "byte for byte (--frames and --show grow slab by slab). A volume of one "
                   "slab (about 1 MiB of samples) has one engine; so have runs with --smooth, "
                   "--decimate, --largest or --min-faces, and a note says so. 1: one "
                   "thread does everything, for single-core devices. Default: one per core "
                   "for volumes of 64 MiB or more, else one engine and a reading thread")
      ->check(CLI::Range(1u, 1024u));
  // For tests and tuning: thin slabs put slab boundaries everywhere in a small volume. Listed
  // in --help: CLI11 leaves the name of a hidden option out of its errors (": Value 2 not in
  // range").
  command
      ->add_option("--slab-slices", args->slab_slices,
                   "Slices per slab with --threads above 1, for tuning (default: about 1 MiB of "
                   "samples a slab, 8 to 128 slices; at least 4)")
      ->transform(whole_number_from(4, std::uint64_t{1} << 30));
  command->add_flag("-q,--quiet", args->quiet, "No progress line and no summary");
  command->callback([args, runner] { run_extract(*args, runner); });
}

}  // namespace mvox
