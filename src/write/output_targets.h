#pragma once
// The one rule that keeps a job from destroying data: no output may replace an input file or
// another output. Files are compared by identity (device and inode, links followed), never by
// spelling, so "-o ./vol.raw", a symbolic or hard link to an input, and /dev/stdout redirected
// onto an input are all caught; outputs that do not exist yet are compared by their path with
// links and "." / ".." resolved.
//
// What needs no check: temporaries are created with fresh names (O_EXCL), and scratch files
// have no name at all (output_file.h, scratch_file.h), so neither can land on an input.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mvox {

// One output of a job as the user named it.
struct OutputTarget {
  std::string path;    // "-" for standard output
  std::string option;  // for messages: "-o", "--image", "--stats"
  std::string noun;    // for messages: "the mesh", "the picture", "the report"
};

// The frames of a picture: frame_NNNN.png in `directory` after every `every` slices and after
// the last one (frame_file_name in surface_picture.h).
struct FramesTarget {
  std::string directory;
  std::uint32_t every = 10;
  std::uint32_t depth = 0;  // slices in the volume
};

// Throws UsageError (exit 2), before any output is created or any slice read, when
// - an output is one of `input_files` ("OUTPUT: is the input INPUT, which the mesh (-o) would
//   replace"), by any name;
// - two outputs are one file or one path, standard output included ("-o - --stats -");
// - a frame would replace an input file or another output.
// Character devices (/dev/null, a terminal) replace nothing and may be named several times.
// `inputs` says whether every input file was found on disk (listed, or opened by its reader):
// then, when no output exists yet, none can be an input, and the inputs are not looked at (a
// stat each, for each of a stack's thousands of slices). An input not yet opened (the mesh of
// `mvox render`) may be missing, and a missing input and a new output may still be one path.
enum class InputFiles { found, not_yet_opened };
void check_output_targets(const std::vector<OutputTarget>& outputs,
                          const std::optional<FramesTarget>& frames,
                          const std::vector<std::string>& input_files, InputFiles inputs);

}  // namespace mvox
