#pragma once
// The input-format rows (read/input_format.h) of headerless samples, told apart by --raw.
namespace mvox {

struct InputFormat;

// --raw WxHxD:TYPE: one volume file (a glob matching one file is fine, a directory is not).
const InputFormat& raw_volume_format();

// --raw WxH:TYPE: one file per slice; a directory contributes all its regular, non-hidden files.
const InputFormat& raw_slices_format();

}  // namespace mvox
