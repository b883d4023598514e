#pragma once
// Turns the user's INPUT arguments (directories, glob patterns, files) into the ordered list of
// slice files a reader walks through.
#include <string>
#include <vector>

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
