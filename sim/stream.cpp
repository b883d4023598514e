#include "stream.h"

namespace mvox {

Status stream_volume(SliceSource& source, Engine& engine, const SliceProgress& progress) {
  SliceView slice;
  std::uint32_t slices_done = 0;
  while (source.next_slice(&slice)) {
    if (Status status = engine.push_slice(slice); status != Status::ok) return status;
    ++slices_done;
    if (progress) progress(slices_done);
  }
  return engine.finish();
}

}  // namespace mvox
