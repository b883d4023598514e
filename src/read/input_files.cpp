#include "read/input_files.h"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "error.h"
#include "read/natural_sort.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

constexpr const char* kImageExtensions[] = {"png", "tif", "tiff", "jpg", "jpeg",
                                            "bmp", "pgm", "pnm",  "ppm"};
constexpr const char* kImageExtensionList = "png, tif, tiff, jpg, jpeg, bmp, pgm, pnm, ppm";

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool is_glob_pattern(const std::string& text) {
  return text.find_first_of("*?[") != std::string::npos;
}

bool is_hidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name[0] == '.';
}

// Why `path`, found in a directory listing or by a pattern, cannot be a slice although it is
// named like one, or "" when it is a regular file (following symbolic links) or is to be
// skipped. Skipping a broken slice would silently close the gap it leaves in the volume, so a
// dangling link, or anything but a regular file or a directory, is an error; so is a directory
// with a slice image's name. Other directories are skipped: raw slice names have no extension
// that would tell them from a folder of notes.
std::string not_a_slice_problem(const fs::path& path, InputKind kind) {
  std::error_code error;
  const fs::file_status target = fs::status(path, error);
  if (fs::is_regular_file(target)) return "";
  if (fs::is_directory(target)) {
    return kind == InputKind::image_stack && has_slice_image_extension(path.string())
               ? "is a directory, not a slice image"
               : "";
  }
  if (target.type() == fs::file_type::not_found && fs::is_symlink(fs::symlink_status(path, error)))
    return "is a dangling symbolic link: its target does not exist";
  if (error) return "cannot read: " + error.message();
  return "is not a regular file (a FIFO, socket or device), not a slice";
}

// Appends the slice files of `directory` to `files`.
void add_directory(const std::string& directory, InputKind kind, BadEntries bad_entries,
                   std::vector<std::string>& files) {
  std::size_t visible_files = 0;
  std::size_t slice_files = 0;
  std::error_code error;
  // Explicit increment with an error code: the range-for form would throw
  // std::filesystem::filesystem_error mid-listing instead of an Error naming the directory.
  for (fs::directory_iterator entry(directory, error), end; !error && entry != end;
       entry.increment(error)) {
    // is_regular_file follows symbolic links, so a link to a slice counts as that slice.
    if (is_hidden(entry->path())) continue;
    const bool named_as_slice =
        kind == InputKind::raw_files || has_slice_image_extension(entry->path().string());
    std::error_code type_error;
    if (!entry->is_regular_file(type_error)) {
      const std::string problem =
          named_as_slice ? not_a_slice_problem(entry->path(), kind) : std::string();
      if (!problem.empty() && bad_entries == BadEntries::refuse)
        throw Error(entry->path().string(), problem);
      continue;
    }
    ++visible_files;
    if (!named_as_slice) continue;
    ++slice_files;
    files.push_back(entry->path().string());
  }
  if (error) throw Error(directory, "cannot list directory: " + error.message());
  if (visible_files == 0)
    throw Error(directory, "directory is empty (no regular, non-hidden files)");
  if (slice_files == 0) {
    throw Error(directory, std::string("directory has no slice images (") + kImageExtensionList +
                               "); for headerless files use --raw");
  }
}

// Appends the regular files matching `pattern` to `files`.
void add_glob(const std::string& pattern, InputKind kind, BadEntries bad_entries,
              std::vector<std::string>& files) {
  glob_t matches{};
  const int result = glob(pattern.c_str(), 0, nullptr, &matches);
  std::vector<std::string> matched;
  if (result == 0) matched.assign(matches.gl_pathv, matches.gl_pathv + matches.gl_pathc);
  globfree(&matches);  // before anything below can throw
  std::size_t added = 0;
  for (const std::string& match : matched) {
    const std::string problem = not_a_slice_problem(match, kind);
    if (!problem.empty() && bad_entries == BadEntries::refuse) throw Error(match, problem);
    std::error_code error;
    if (!fs::is_regular_file(match, error)) continue;  // a directory
    files.push_back(match);
    ++added;
  }
  if (result == GLOB_NOSPACE) throw Error(pattern, "out of memory while expanding the pattern");
  if (result == GLOB_ABORTED) throw Error(pattern, "cannot read a directory of the pattern");
  if (added == 0) throw Error(pattern, "no file matches this pattern");
}

}  // namespace

bool has_slice_image_extension(const std::string& path) {
  const std::string extension = lower(fs::path(path).extension().string());
  if (extension.size() < 2) return false;  // no extension, or just "."
  const std::string bare = extension.substr(1);
  return std::any_of(std::begin(kImageExtensions), std::end(kImageExtensions),
                     [&](const char* known) { return bare == known; });
}

std::vector<std::string> list_input_files(const std::vector<std::string>& inputs, InputKind kind,
                                          BadEntries bad_entries) {
  if (inputs.empty()) throw Error("INPUT", "no input files or directories given");
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    std::error_code error;
    const fs::file_status status = fs::status(input, error);
    if (error && status.type() != fs::file_type::not_found) throw Error(input, error.message());
    if (fs::is_directory(status)) {
      add_directory(input, kind, bad_entries, files);
    } else if (fs::exists(status)) {
      files.push_back(input);
    } else if (is_glob_pattern(input)) {
      add_glob(input, kind, bad_entries, files);
    } else {
      throw Error(input, "no such file or directory");
    }
  }
  natural_sort(files);
  return files;
}

std::string inputs_label(const std::vector<std::string>& inputs) {
  if (inputs.size() == 1) return inputs[0];
  return inputs.front() + " ... " + inputs.back() + " (" + std::to_string(inputs.size()) +
         " inputs)";
}

}  // namespace mvox
