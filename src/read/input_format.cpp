#include "read/input_format.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <string>
#include <utility>

#include "error.h"
#include "read/dicom/dicom_input.h"
#include "read/file_names.h"
#include "read/image_stack/image_stack_input.h"
#include "read/input_name.h"
#include "read/metaimage/metaimage_file.h"
#include "read/nifti/nifti_file.h"
#include "read/nrrd/nrrd_file.h"
#include "read/raw/raw_input.h"
#include "read/stored_volume_source.h"
#include "read/tiff/tiff_input.h"
#include "write/standard_descriptors.h"

namespace mvox {

InputRequest::InputRequest(std::vector<std::string> inputs, InputOptions options)
    : inputs_(std::move(inputs)), options_(std::move(options)) {}

const std::vector<std::string>& InputRequest::files(InputKind kind, BadEntries bad_entries) const {
  std::optional<std::vector<std::string>>& listed =
      listed_[(kind == InputKind::raw_files ? 2 : 0) + (bad_entries == BadEntries::skip ? 1 : 0)];
  if (!listed) {
    if (!scan_) scan_.emplace(inputs_);
    listed = scan_->files(kind, bad_entries);
  }
  return *listed;
}

const std::vector<const InputFormat*>& input_formats() {
  static const std::vector<const InputFormat*> formats = {
      &dicom_series_format(), &nrrd_volume_format(), &metaimage_volume_format(),
      &nifti_volume_format(), &tiff_stack_format(),  &raw_volume_format(),
      &raw_slices_format(),   &image_stack_format()};
  return formats;
}

namespace {

// What an input that is neither a file nor a directory is, for the refusal below; null for a
// file, a directory, or a path that does not exist (the formats name that). stat() follows
// links and, unlike open(), does not wait for a FIFO's writer.
const char* stream_kind(const std::string& input) {
  struct stat status {};
  if (::stat(input.c_str(), &status) != 0) return nullptr;
  // Standard input, or /dev/fd/63 for <(zcat ...), is "a pipe" to the user; a name in a
  // directory, a FIFO.
  if (S_ISFIFO(status.st_mode)) return descriptor_named_by(input) ? "a pipe" : "a FIFO";
  if (S_ISCHR(status.st_mode) || S_ISBLK(status.st_mode)) return "a device";
  if (S_ISSOCK(status.st_mode)) return "a socket";
  return nullptr;
}

// A pipe (standard input, a FIFO) can be read once, in order, and the formats are told apart by
// opening each input and reading its first bytes: what that read took was missing for the
// reader that followed ("not an image"), or a FIFO was opened a second time and mvox waited
// for a writer that had gone, for ever. Only a raw volume, whose layout --raw gives, is read
// from one; anything else is refused here, before any input is opened.
void refuse_streams_without_raw(const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs)
    if (const char* kind = stream_kind(input))
      throw UsageError(input_name(input),
                       std::string("is ") + kind +
                           ", which mvox reads once, in order, as a raw volume: give --raw "
                           "WxHxD:TYPE, or save it to a file to read another format");
}

}  // namespace

OpenedInput open_input(const std::vector<std::string>& inputs, const InputOptions& options) {
  if (options.dicom.force && options.raw)
    throw UsageError("--dicom", "cannot be combined with --raw");
  if (!options.raw) refuse_streams_without_raw(inputs);
  const InputRequest request(inputs, options);
  for (const InputFormat* format : input_formats()) {
    if (!format->claims(request)) continue;
    if (!options.dicom.series_uid.empty() && format != &dicom_series_format())
      throw UsageError("--series",
                       "applies to DICOM input only, and INPUT is not DICOM (use --dicom for "
                       "DICOM files without the DICM preamble or a .dcm name)");
    return format->open(request);
  }
  throw Error("INPUT", "no reader takes it");  // image stacks take anything without --raw
}

std::unique_ptr<SliceSource> open_slice_source(const std::vector<std::string>& inputs,
                                               const std::optional<RawFormat>& raw,
                                               const DicomChoice& dicom) {
  InputOptions options;
  options.raw = raw;
  options.dicom = dicom;
  return open_input(inputs, options).source;
}

bool has_extension(const std::string& path, std::initializer_list<const char*> extensions) {
  // By the end of the name, so that double extensions (.nii.gz) work.
  std::string name = file_name_of(path);
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return std::any_of(extensions.begin(), extensions.end(), [&](const char* wanted) {
    const std::size_t length = std::char_traits<char>::length(wanted);
    return name.size() > length && name.compare(name.size() - length, length, wanted) == 0;
  });
}

bool claims_headered_volume(const InputRequest& request, const char* format_name,
                            std::initializer_list<const char*> extensions) {
  if (request.options().raw) {
    // --raw describes headerless files; a headered file describes itself: asking for both is
    // a usage error, found from the names alone, before any file is opened.
    for (const std::string& input : request.inputs())
      if (has_extension(input, extensions))
        throw UsageError(
            "--raw", input + " is a " + format_name + " file with its own header; leave --raw out");
    return false;
  }
  const std::vector<std::string>& files = request.files(InputKind::image_stack);
  return std::any_of(files.begin(), files.end(),
                     [&](const std::string& file) { return has_extension(file, extensions); });
}

OpenedInput open_headered_volume(
    const InputRequest& request, const char* format_name,
    std::initializer_list<const char*> extensions,
    std::unique_ptr<StoredVolumeSource> (*open_file)(const std::string&)) {
  const std::vector<std::string>& files = request.files(InputKind::image_stack);
  const auto header = std::find_if(files.begin(), files.end(), [&](const std::string& file) {
    return has_extension(file, extensions);
  });
  if (files.size() != 1)
    throw Error(*header, std::string("is a ") + format_name +
                             " volume, which must be the only input (got " +
                             std::to_string(files.size()) + " files)");
  std::unique_ptr<StoredVolumeSource> volume = open_file(*header);
  OpenedInput opened;
  opened.files = files;
  if (volume->data_path() != *header) opened.files.push_back(volume->data_path());
  opened.source = std::move(volume);
  return opened;
}

}  // namespace mvox
