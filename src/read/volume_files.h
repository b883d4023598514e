#pragma once
// Inputs that are volume files rather than one image per slice: NRRD (.nrrd, .nhdr),
// MetaImage (.mhd, .mha) and TIFF stacks (.tif, .tiff, any number of pages each). Chosen by
// extension, case-insensitive.
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"

namespace mvox {

// Formats whose files carry their own header (and so never take --raw).
enum class HeaderedFormat { none, nrrd, metaimage };

HeaderedFormat headered_format(const std::string& path);  // by extension
const char* headered_format_name(HeaderedFormat format);  // "NRRD", "MetaImage"

// The reader for the listed input files when they are volume files, or nullptr when they are an
// image stack for ImageStackSource:
// - a NRRD or MetaImage file must be the only file (one header is one volume);
// - when every file is a TIFF: TiffStackSource, all pages of all files in order, so one
//   multi-page TIFF, several of them, and single-page TIFF slices are all stacks;
// - TIFF files mixed with other images stay with ImageStackSource, which reads one page per
//   file, so a multi-page TIFF among them is refused instead of losing its other pages.
// A NRRD or MetaImage header that keeps its samples in another file adds that file's path to
// `*data_files` (when not null). Throws mvox::Error naming the file.
std::unique_ptr<SliceSource> open_volume_files(const std::vector<std::string>& files,
                                               std::vector<std::string>* data_files = nullptr);

}  // namespace mvox
