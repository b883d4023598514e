#include "mvox/status.h"

#include "mvox/slice.h"

namespace mvox {

const char* status_message(Status status) {
  switch (status) {
    case Status::ok: return "ok";
    case Status::invalid_argument: return "invalid argument";
    case Status::workspace_misaligned: return "workspace not aligned to 8 bytes";
    case Status::workspace_too_small: return "workspace too small";
    case Status::not_initialised: return "engine not initialised";
    case Status::slice_size_mismatch: return "slice size differs from the first slice";
    case Status::already_finished: return "volume already finished";
    case Status::sink_refused: return "output refused the data";
    case Status::vertex_index_overflow: return "vertex index overflow";
  }
  return "unknown status";
}

const char* sample_type_name(SampleType type) {
  switch (type) {
    case SampleType::u8: return "u8";
    case SampleType::u16: return "u16";
    case SampleType::i16: return "i16";
    case SampleType::f32: return "f32";
  }
  return "unknown";
}

}  // namespace mvox
