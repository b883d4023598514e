#include "write/output_targets.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "error.h"
#include "picture/surface_picture.h"
#include "write/file_identity.h"
#include "write/standard_descriptors.h"

namespace mvox {
namespace {

// What a path refers to, as far as "is it the same file" goes.
struct Resolved {
  std::optional<int> descriptor;         // when it names an open descriptor
  std::optional<FileIdentity> identity;  // when the file exists (or the descriptor is open)
  std::string canonical;                 // absolute, links and dots resolved where they exist;
                                         // only for a path that does not exist (yet)
};

Resolved resolve(const std::string& path, int dash_descriptor) {
  Resolved resolved;
  resolved.descriptor =
      path == "-" ? std::optional<int>(dash_descriptor) : descriptor_named_by(path);
  if (resolved.descriptor) {
    resolved.identity = identity_of_descriptor(*resolved.descriptor);
    return resolved;
  }
  resolved.identity = identity_of_path(path);
  // An existing file is known by its identity; resolving every link of its path as well cost
  // a readlink and a stat per component, for each of a stack's thousands of slices.
  if (resolved.identity) return resolved;
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(path, error);
  if (!error) resolved.canonical = std::filesystem::weakly_canonical(absolute, error).string();
  if (error) resolved.canonical = absolute.lexically_normal().string();
  return resolved;
}

// True when writing `a` would land on `b`. A character device (/dev/null, a terminal) reached
// by name replaces nothing, so it is never "the same" unless both name one descriptor, where
// two outputs would run together.
bool same_file(const Resolved& a, const Resolved& b) {
  if (a.descriptor && b.descriptor && *a.descriptor == *b.descriptor) return true;
  if (a.identity && b.identity) return *a.identity == *b.identity && !a.identity->character_device;
  if (a.identity || b.identity) return false;  // one exists, the other does not
  return !a.canonical.empty() && a.canonical == b.canonical;
}

std::string parent_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

std::string name_of(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

// True when the frames will include one named `name`.
bool is_frame_name(const FramesTarget& frames, const std::string& name) {
  constexpr std::size_t kPrefix = 6, kSuffix = 4;  // "frame_", ".png"
  if (name.size() <= kPrefix + kSuffix || name.compare(0, kPrefix, "frame_") != 0 ||
      name.compare(name.size() - kSuffix, kSuffix, ".png") != 0)
    return false;
  const std::string digits = name.substr(kPrefix, name.size() - kPrefix - kSuffix);
  if (digits.size() > 10 || digits.find_first_not_of("0123456789") != std::string::npos)
    return false;
  const std::uint64_t slices = std::stoull(digits);
  if (slices == 0 || slices > frames.depth) return false;
  const bool written = slices == frames.depth || (frames.every > 0 && slices % frames.every == 0);
  return written && frame_file_name(static_cast<std::uint32_t>(slices), frames.depth) == name;
}

std::string shown(const OutputTarget& output) {
  return output.noun + " (" + output.option + " " + output.path + ")";
}

std::string subject_of(const OutputTarget& output) {
  return output.path == "-" ? "standard output" : output.path;
}

}  // namespace

void check_output_targets(const std::vector<OutputTarget>& outputs,
                          const std::optional<FramesTarget>& frames,
                          const std::vector<std::string>& input_files, InputFiles inputs_known) {
  std::vector<Resolved> resolved;
  for (const OutputTarget& output : outputs) resolved.push_back(resolve(output.path, 1));
  // An output that does not exist (an open descriptor has an identity too) can replace no
  // existing file, so inputs found on disk need looking at only when some output exists.
  const bool some_output_exists = std::any_of(
      resolved.begin(), resolved.end(), [](const Resolved& r) { return r.identity.has_value(); });
  std::vector<Resolved> inputs;
  if (some_output_exists || inputs_known == InputFiles::not_yet_opened) {
    inputs.reserve(input_files.size());
    for (const std::string& input : input_files) inputs.push_back(resolve(input, 0));
  }

  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      if (!same_file(resolved[i], inputs[k])) continue;
      const std::string& input = input_files[k];
      const std::string which = input == outputs[i].path
                                    ? std::string("is an input file")
                                    : "is the input " + input + " by another name";
      throw UsageError(subject_of(outputs[i]),
                       which + ", and " + outputs[i].noun + " (" + outputs[i].option +
                           ") would replace it; choose another output name");
    }
    for (std::size_t k = 0; k < i; ++k)
      if (same_file(resolved[i], resolved[k]))
        throw UsageError(subject_of(outputs[i]),
                         "is both " + shown(outputs[k]) + " and " + shown(outputs[i]));
  }
  if (!frames || frames->directory.empty()) return;

  // A frame lands on a file when that file's directory is the frames directory and its name is
  // one the frames will take.
  const Resolved directory = resolve(frames->directory, -1);
  auto lands_on = [&](const std::string& path) {
    if (path == "-" || descriptor_named_by(path) || !is_frame_name(*frames, name_of(path)))
      return false;
    return same_file(resolve(parent_of(path), -1), directory);
  };
  for (const std::string& input : input_files)
    if (lands_on(input))
      throw UsageError(
          "--frames " + frames->directory,
          "a frame would replace the input " + input + "; write the frames into another directory");
  for (const OutputTarget& output : outputs)
    if (lands_on(output.path))
      throw UsageError(subject_of(output), "is both " + shown(output) +
                                               " and a frame of --frames " + frames->directory);
}

}  // namespace mvox
