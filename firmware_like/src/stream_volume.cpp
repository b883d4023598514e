#include "mvox/stream_volume.h"

namespace mvox {

Status stream_volume(SliceSource& source, Engine& engine, SliceProgress progress,
                     SliceWindow* window) {
  SliceView slice;
  std::uint32_t slices_done = 0;
  auto push = [&](const SliceView& view) {
    const Status status = engine.push_slice(view);
    if (status == Status::ok && progress) progress(++slices_done);
    return status;
  };
  while (source.next_slice(&slice)) {
    if (!window) {
      if (const Status status = push(slice); status != Status::ok) return status;
      continue;
    }
    if (const Status status = window->push(slice); status != Status::ok) return status;
    if (window->slices() >= 2)  // the engine takes the slice before the newest
      if (const Status status = push(window->slice(window->slices() - 2)); status != Status::ok)
        return status;
  }
  if (window && window->slices() >= 1)
    if (const Status status = push(window->slice(window->slices() - 1)); status != Status::ok)
      return status;
  return engine.finish();
}

}  // namespace mvox
