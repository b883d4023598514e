#pragma once
// The one table of input formats: which reader takes the command line's INPUT arguments and
// options, and opening it. Each format is a row, {name, claims, open}, defined in its own folder
// (read/dicom/, read/nrrd/, ...); the first row in the order of input_formats() that claims the
// input opens it. Adding a format is one folder and one row.
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/dicom/dicom_input.h"
#include "read/input_files.h"
#include "read/raw/raw_format.h"

namespace mvox {

// What the command line says about the input besides the INPUT arguments.
struct InputOptions {
  std::optional<RawFormat> raw;  // --raw WxH[xD]:TYPE
  DicomChoice dicom;             // --dicom, --series, and where notes go
};

// The INPUT arguments and options, with their file listings made once and shared by the rows
// that look at them.
class InputRequest {
 public:
  InputRequest(std::vector<std::string> inputs, InputOptions options);

  const std::vector<std::string>& inputs() const { return inputs_; }
  const InputOptions& options() const { return options_; }
  // list_input_files(inputs(), kind, bad_entries), from one InputScan of the inputs made on
  // first use. Throws as list_input_files does.
  const std::vector<std::string>& files(InputKind kind,
                                        BadEntries bad_entries = BadEntries::refuse) const;

 private:
  std::vector<std::string> inputs_;
  InputOptions options_;
  mutable std::optional<InputScan> scan_;
  // Listings by kind and rule: image_stack, raw_files, raw_files skipping bad entries (DICOM
  // detection); image_stack skipping them is asked by no row.
  mutable std::optional<std::vector<std::string>> listed_[4];
};

// An open input and every file it reads.
struct OpenedInput {
  std::unique_ptr<SliceSource> source;
  // The slice files, headers and data files the source reads (for DICOM, every file INPUT
  // offered, DICOM or not), so that no output can replace one of them (output_targets.h).
  std::vector<std::string> files;
};

struct InputFormat {
  const char* name;  // "DICOM series", "NRRD volume", ... for documentation and messages
  // True when this format reads the request. May throw UsageError for a combination it never
  // takes (--raw with a file that has its own header), and mvox::Error from listing the files.
  bool (*claims)(const InputRequest& request);
  // Opens the request's reader, reading headers only. Throws mvox::Error naming the file.
  OpenedInput (*open)(const InputRequest& request);
};

// The rows, in the order they are asked: DICOM series, NRRD, MetaImage, NIfTI, TIFF stacks, raw
// volume, raw slices, and image stacks, which take whatever is left.
const std::vector<const InputFormat*>& input_formats();

// Opens `inputs` with the first format that claims them. Throws UsageError for options that do
// not fit the input (--series for input that is not DICOM, --raw with a headered file, --dicom
// with --raw, a pipe or device without --raw: only a raw volume is read from one), and
// mvox::Error from the reader.
OpenedInput open_input(const std::vector<std::string>& inputs, const InputOptions& options);

// open_input's source alone, for callers that need no file list (tests, benchmarks).
std::unique_ptr<SliceSource> open_slice_source(const std::vector<std::string>& inputs,
                                               const std::optional<RawFormat>& raw,
                                               const DicomChoice& dicom = {});

// ROWS' HELPERS ----------------------------------------------------------------------------------

// True when `path` ends in one of `extensions` (".nrrd", ...), ignoring case.
bool has_extension(const std::string& path, std::initializer_list<const char*> extensions);

// For formats whose files carry their own header (NRRD, MetaImage), named by extension: claims
// the request when a listed file has one of `extensions`. With --raw, an INPUT named so is a
// usage error ("--raw: X is a NAME file with its own header; leave --raw out").
bool claims_headered_volume(const InputRequest& request, const char* format_name,
                            std::initializer_list<const char*> extensions);

class StoredVolumeSource;

// Opens a claimed headered volume with `open_file`: it must be the only listed file (one header
// is one volume); the files read are the header and, when the samples live apart, its data file.
OpenedInput open_headered_volume(
    const InputRequest& request, const char* format_name,
    std::initializer_list<const char*> extensions,
    std::unique_ptr<StoredVolumeSource> (*open_file)(const std::string&));

}  // namespace mvox
