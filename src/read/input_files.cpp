#include "read/input_files.h"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <system_error>
#include <utility>

#include "read/file_names.h"
#include "read/input_name.h"
#include "read/natural_sort.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

constexpr const char* kImageExtensions[] = {"png", "tif", "tiff", "jpg", "jpeg",
                                            "bmp", "pgm", "pnm",  "ppm"};
constexpr const char* kImageExtensionList = "png, tif, tiff, jpg, jpeg, bmp, pgm, pnm, ppm";

bool is_glob_pattern(const std::string& text) {
  return text.find_first_of("*?[") != std::string::npos;
}

bool is_hidden(const std::string& path) {
  const std::string name = file_name_of(path);
  return !name.empty() && name[0] == '.';
}

// Why `path`, not a regular file by its directory entry, cannot be a slice whatever the input
// kind: a dangling link, something unreadable, a FIFO, socket or device. "" for a directory
// (set in `nature`; whether a directory may be named like a slice depends on the kind) and for
// a file that turned regular since it was listed (skipped, as a non-regular entry always was).
std::string unusable_problem(const std::string& path, bool& is_directory) {
  std::error_code error;
  const fs::file_status target = fs::status(path, error);
  is_directory = fs::is_directory(target);
  if (is_directory || fs::is_regular_file(target)) return "";
  if (target.type() == fs::file_type::not_found && fs::is_symlink(fs::symlink_status(path, error)))
    return "is a dangling symbolic link: its target does not exist";
  if (error) return "cannot read: " + error.message();
  return "is not a regular file (a FIFO, socket or device), not a slice";
}

}  // namespace

bool has_slice_image_extension(const std::string& path) {
  const std::string extension = lowercase_extension(path);
  if (extension.size() < 2) return false;  // no extension, or just "."
  const std::string bare = extension.substr(1);
  return std::any_of(std::begin(kImageExtensions), std::end(kImageExtensions),
                     [&](const char* known) { return bare == known; });
}

InputScan::InputScan(std::vector<std::string> inputs) : inputs_(std::move(inputs)) {
  for (const std::string& input : inputs_) {
    Argument argument;
    argument.input = input;
    argument.first = entries_.size();
    std::error_code error;
    const fs::file_status status = fs::status(input, error);
    if (error && status.type() != fs::file_type::not_found) {
      argument.error = Error(input, error.message());
    } else if (fs::is_directory(status)) {
      argument.form = Form::directory;
      scan_directory(argument);
    } else if (fs::exists(status)) {
      entries_.push_back({input, Nature::regular, ""});  // taken as given: the user named it
    } else if (is_glob_pattern(input)) {
      argument.form = Form::pattern;
      scan_pattern(argument);
    } else {
      argument.error = Error(input, "no such file or directory");
    }
    argument.last = entries_.size();
    arguments_.push_back(std::move(argument));
  }
  sorted_.resize(entries_.size());
  std::iota(sorted_.begin(), sorted_.end(), 0u);
  // natural_less is a total order, so filtering the sorted names gives each listing in the
  // order sorting it would.
  std::sort(sorted_.begin(), sorted_.end(), [&](std::uint32_t a, std::uint32_t b) {
    return natural_less(entries_[a].path, entries_[b].path);
  });
}

void InputScan::scan_directory(Argument& argument) {
  std::error_code error;
  // Explicit increment with an error code: the range-for form would throw
  // std::filesystem::filesystem_error mid-listing instead of an Error naming the directory.
  for (fs::directory_iterator entry(argument.input, error), end; !error && entry != end;
       entry.increment(error)) {
    std::string path = entry->path().string();
    if (is_hidden(path)) continue;
    // is_regular_file follows symbolic links, so a link to a slice counts as that slice; it asks
    // the file system only for links and entries whose type the listing did not give.
    std::error_code type_error;
    if (entry->is_regular_file(type_error)) {
      entries_.push_back({std::move(path), Nature::regular, ""});
      continue;
    }
    if (!entry->is_symlink(type_error) && entry->is_directory(type_error)) {  // from the listing
      entries_.push_back({std::move(path), Nature::directory, ""});
      continue;
    }
    bool is_directory = false;
    std::string problem = unusable_problem(path, is_directory);
    entries_.push_back(
        {std::move(path), is_directory ? Nature::directory : Nature::unusable, std::move(problem)});
  }
  if (error) argument.error = Error(argument.input, "cannot list directory: " + error.message());
}

void InputScan::scan_pattern(Argument& argument) {
  glob_t matches{};
  const int result = glob(argument.input.c_str(), 0, nullptr, &matches);
  std::vector<std::string> matched;
  if (result == 0) matched.assign(matches.gl_pathv, matches.gl_pathv + matches.gl_pathc);
  globfree(&matches);
  for (std::string& match : matched) {
    std::error_code error;
    const fs::file_status target = fs::status(match, error);  // the one stat of a match
    if (fs::is_regular_file(target)) {
      entries_.push_back({std::move(match), Nature::regular, ""});
      continue;
    }
    bool is_directory = false;
    std::string problem = unusable_problem(match, is_directory);
    entries_.push_back({std::move(match), is_directory ? Nature::directory : Nature::unusable,
                        std::move(problem)});
  }
  if (result == GLOB_NOSPACE)
    argument.error = Error(argument.input, "out of memory while expanding the pattern");
  else if (result == GLOB_ABORTED)
    argument.error = Error(argument.input, "cannot read a directory of the pattern");
}

std::vector<std::string> InputScan::files(InputKind kind, BadEntries bad_entries) const {
  if (inputs_.empty()) throw Error("INPUT", "no input files or directories given");
  std::vector<bool> taken(entries_.size(), false);
  // In the order of the arguments, so that the first problem met is the one reported.
  for (const Argument& argument : arguments_) {
    std::size_t usable = 0;       // regular, non-hidden files
    std::size_t slice_files = 0;  // those a slice of this kind may be
    for (std::size_t i = argument.first; i < argument.last; ++i) {
      const Entry& entry = entries_[i];
      // In a directory only names a slice of this kind could have count; a pattern or an
      // explicit file named what it wants.
      const bool named_as_slice = argument.form != Form::directory ||
                                  kind == InputKind::raw_files ||
                                  has_slice_image_extension(entry.path);
      if (entry.nature != Nature::regular) {
        const std::string problem =
            entry.nature == Nature::directory
                ? (kind == InputKind::image_stack && has_slice_image_extension(entry.path)
                       ? "is a directory, not a slice image"
                       : "")
                : entry.problem;
        if (named_as_slice && !problem.empty() && bad_entries == BadEntries::refuse)
          throw Error(entry.path, problem);
        continue;
      }
      ++usable;
      if (!named_as_slice) continue;
      ++slice_files;
      taken[i] = true;
    }
    if (argument.error) throw *argument.error;
    if (argument.form == Form::directory) {
      if (usable == 0)
        throw Error(argument.input, "directory is empty (no regular, non-hidden files)");
      if (slice_files == 0)
        throw Error(argument.input, std::string("directory has no slice images (") +
                                        kImageExtensionList + "); for headerless files use --raw");
    } else if (argument.form == Form::pattern && slice_files == 0) {
      throw Error(argument.input, "no file matches this pattern");
    }
  }
  std::vector<std::string> files;
  for (const std::uint32_t i : sorted_)
    if (taken[i]) files.push_back(entries_[i].path);
  return files;
}

std::vector<std::string> list_input_files(const std::vector<std::string>& inputs, InputKind kind,
                                          BadEntries bad_entries) {
  return InputScan(inputs).files(kind, bad_entries);
}

std::string inputs_label(const std::vector<std::string>& inputs) {
  if (inputs.size() == 1) return input_name(inputs[0]);
  return inputs.front() + " ... " + inputs.back() + " (" + std::to_string(inputs.size()) +
         " inputs)";
}

}  // namespace mvox
