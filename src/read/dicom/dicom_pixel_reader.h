#pragma once
// Decodes one frame of a DICOM file with GDCM: native (little or big endian, explicit or
// implicit VR) and every compression Debian's GDCM has codecs for (RLE, JPEG lossless and lossy,
// JPEG-LS, JPEG 2000). GDCM is linked by the DICOM module (modules/dicom_codecs/), loaded at
// the first use, so that runs without DICOM never load it.
#include <cstdint>
#include <string>
#include <vector>

#include "read/dicom/dicom_header.h"

namespace mvox {

class DicomPixelReader {
 public:
  // Loads the DICOM module now, so that a run finds a missing module before it starts, and
  // counts GDCM's memory as the program's when it plans its own. Throws mvox::Error(subject,
  // reason) when the module cannot be loaded: the reason names it and how to install GDCM.
  void load(const std::string& subject) const;

  // Decodes frame `frame` of `expected.path` into `decoded` (resized to
  // dicom_frame_bytes(expected)): expected.bits_allocated-wide samples, native byte order, rows
  // packed. Single-frame files are read whole; a multi-frame file's frame alone, with GDCM's
  // region reader, so that memory stays at one frame.
  // The file's header is first read again (read_dicom_image_header, with all its checks), so
  // that a file that changed since it was scanned cannot reach GDCM malformed or different.
  // Throws mvox::Error(path, problem) when the file cannot be read, GDCM cannot decode its
  // transfer syntax (the problem names it), or the decoded image is not what the header said.
  void read_frame(const DicomImageHeader& expected, std::uint32_t frame,
                  std::vector<char>& decoded);
};

// "JPEG 2000 Image Compression (Lossless Only) (1.2.840.10008.1.2.4.90)", or the bare UID when
// GDCM does not know its name. Loads the DICOM module (mvox::Error when it cannot).
std::string transfer_syntax_text(const std::string& uid);

}  // namespace mvox
