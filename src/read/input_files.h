#pragma once
// Turns the user's INPUT arguments (directories, glob patterns, files) into the ordered list of
// slice files a reader walks through.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "error.h"

namespace mvox {

// What the files will be read as; it decides which files of a directory count as slices.
enum class InputKind {
  image_stack,  // a directory contributes only files with a slice image extension
  raw_files,    // a directory contributes all its regular, non-hidden files
};

// True when `path` ends in an image extension readers accept, case-insensitive:
// png, tif, tiff, jpg, jpeg, bmp, pgm, pnm, ppm.
bool has_slice_image_extension(const std::string& path);

// What list_input_files does with an entry that cannot be a slice although it is named like
// one (a dangling link, a FIFO, ...): refuse it, or leave it out (to look at the other files
// only, as DICOM detection does before the real listing refuses it).
enum class BadEntries { refuse, skip };

// One look at the file system for the INPUT arguments: each directory listed, each pattern
// expanded, and what each entry is, once. Several readers ask which files the input holds (DICOM
// detection, the headered formats, the reader that opens it), each with its own rule; before,
// each asked the file system again, and a stack of 1,024 slices given as a pattern cost 5,000
// stat calls (25 ms, more than the rest of a --dry-run) before its first slice was read. Now a
// pattern's file costs one stat and a directory's file or subdirectory none (its type comes with
// the listing; links and stranger entries cost more), and the names are sorted once.
class InputScan {
 public:
  // Looks at `inputs`. Never throws for what it finds: a missing input or a directory that
  // cannot be listed is reported by files(), in the order list_input_files reports it.
  explicit InputScan(std::vector<std::string> inputs);

  // The files for `kind`, as list_input_files(inputs, kind, bad_entries) gives them.
  std::vector<std::string> files(InputKind kind, BadEntries bad_entries) const;

 private:
  enum class Nature : std::uint8_t { regular, directory, unusable };
  struct Entry {
    std::string path;
    Nature nature = Nature::regular;
    std::string problem;  // for unusable entries: why they cannot be a slice ("" to skip them)
  };
  enum class Form : std::uint8_t { file, directory, pattern };
  struct Argument {
    std::string input;
    Form form = Form::file;
    std::size_t first = 0, last = 0;  // its entries, entries_[first, last)
    std::optional<Error> error;       // thrown after its entries are looked at
  };

  void scan_directory(Argument& argument);
  void scan_pattern(Argument& argument);

  std::vector<std::string> inputs_;
  std::vector<Argument> arguments_;
  std::vector<Entry> entries_;         // in the order the arguments gave them
  std::vector<std::uint32_t> sorted_;  // entries_ indices in natural order
};

// Expands `inputs` into one naturally sorted list of files (natural_sort.h, on the whole path).
// Each input is, in this order of preference:
// - an existing directory: its regular, non-hidden files (not recursive), filtered by `kind`;
// - an existing path: taken as a file as given (no extension filter: the user named it);
// - a path containing *, ? or [: a POSIX glob(3) pattern; matches that are directories are
//   skipped, hidden files match only when the pattern says so (glob's own rule).
// An entry of a directory named like a slice (image_stack: with a slice image extension;
// raw_files: any non-hidden name), or a match of a pattern, that is a dangling symbolic link,
// a FIFO, socket or device, or (image_stack) a directory, is an error naming it: skipping it
// would silently leave a slice out of the volume (with BadEntries::skip it is left out).
// Throws mvox::Error naming the input when it does not exist, a pattern matches no file, a
// directory is empty or holds no slice images, or `inputs` is empty (subject "INPUT").
std::vector<std::string> list_input_files(const std::vector<std::string>& inputs, InputKind kind,
                                          BadEntries bad_entries = BadEntries::refuse);

// The INPUT arguments as one name for messages: the input itself, or "first ... last (N inputs)".
std::string inputs_label(const std::vector<std::string>& inputs);

}  // namespace mvox
