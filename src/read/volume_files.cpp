#include "read/volume_files.h"

#include <algorithm>
#include <filesystem>

#include "error.h"
#include "read/header_text.h"
#include "read/metaimage/metaimage_file.h"
#include "read/nrrd/nrrd_file.h"
#include "read/stored_volume_source.h"
#include "read/tiff/tiff_stack_source.h"

namespace mvox {

HeaderedFormat headered_format(const std::string& path) {
  const std::string extension = lowercase(std::filesystem::path(path).extension().string());
  if (extension == ".nrrd" || extension == ".nhdr") return HeaderedFormat::nrrd;
  if (extension == ".mhd" || extension == ".mha") return HeaderedFormat::metaimage;
  return HeaderedFormat::none;
}

const char* headered_format_name(HeaderedFormat format) {
  switch (format) {
    case HeaderedFormat::nrrd: return "NRRD";
    case HeaderedFormat::metaimage: return "MetaImage";
    case HeaderedFormat::none: break;
  }
  return "headerless";
}

std::unique_ptr<SliceSource> open_volume_files(const std::vector<std::string>& files,
                                               std::vector<std::string>* data_files) {
  for (const std::string& file : files) {
    const HeaderedFormat format = headered_format(file);
    if (format == HeaderedFormat::none) continue;
    if (files.size() != 1) {
      throw Error(file, std::string("is a ") + headered_format_name(format) +
                            " volume, which must be the only input (got " +
                            std::to_string(files.size()) + " files)");
    }
    std::unique_ptr<StoredVolumeSource> volume =
        format == HeaderedFormat::nrrd ? open_nrrd_volume(file) : open_metaimage_volume(file);
    if (data_files && volume->data_path() != file) data_files->push_back(volume->data_path());
    return volume;
  }
  const auto tiff_count = std::count_if(files.begin(), files.end(), has_tiff_extension);
  if (tiff_count > 0 && static_cast<std::size_t>(tiff_count) == files.size()) {
    return std::make_unique<TiffStackSource>(files);
  }
  for (const std::string& file : files) {
    if (!has_tiff_extension(file)) continue;
    const std::uint64_t pages = tiff_page_count(file);
    if (pages > 1) {
      throw Error(file, "is a TIFF stack of " + std::to_string(pages) +
                            " pages among other images; give TIFF stacks without other image "
                            "types");
    }
  }
  return nullptr;
}

}  // namespace mvox
