#pragma once
// Checks compressed pixel data against the DICOM header before GDCM decodes it. GDCM sizes its
// output from the header and trusts the codestream to agree: when they disagree it corrupts the
// heap (JPEG 2000) or aborts on an assertion (JPEG-LS), and a JPEG 2000 fragment without an end
// marker also aborts it. So each frame's codestream header must describe the image the DICOM
// header does, and each frame must end with its end marker.
#include <string>
#include <vector>

#include "read/dicom/dicom_file_scan.h"

namespace mvox {

struct DicomImageHeader;

// The problem with `fragments` (the fragments after the basic offset table) for an image of
// `header`'s size, bits and frames in transfer syntax header.transfer_syntax_uid, or "" when
// there is none. Checked, by transfer syntax:
// - JPEG (1.2.840.10008.1.2.4.50 .. .70) and JPEG-LS (.80, .81): each frame starts with SOI
//   (FFD8) and ends with EOI (FFD9, then zero padding at most); its SOF or SOF55 segment, when
//   found in the first kDicomFragmentHeadBytes, gives Rows, Columns, one component and a
//   precision of at most BitsAllocated;
// - JPEG 2000 (.90 .. .93): each frame starts with SOC (FF4F) and SIZ, or a JP2 signature box
//   with them inside, and ends with EOC (FFD9); SIZ gives Columns x Rows, one component of at
//   most BitsAllocated bits, no subsampling;
// - RLE (1.2.840.10008.1.2.5): each frame's 64-byte header has BitsAllocated / 8 segments at
//   increasing offsets inside the fragment.
// A frame is one fragment when there are as many fragments as frames; a single-frame image may
// also span several fragments. Other transfer syntaxes are not checked here.
std::string compressed_pixel_data_problem(const std::vector<DicomFragment>& fragments,
                                          const DicomImageHeader& header);

}  // namespace mvox
