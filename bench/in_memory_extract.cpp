#include "in_memory_extract.h"

#include <chrono>

#include "mvox/counting_sink.h"
#include "mvox/workspace_buffer.h"

namespace mvox::bench {

double extract_in_memory(const LoadedVolume& volume, double threshold, const EngineOptions& options,
                         EngineCounters* counters) {
  using Clock = std::chrono::steady_clock;
  const VolumeInfo& info = volume.info;
  WorkspaceBuffer workspace(engine_workspace_bytes(info.width, info.height, options));
  CountingSink sink;
  Engine engine;
  const auto start = Clock::now();
  if (engine.init(workspace.data(), workspace.bytes(), info.width, info.height, threshold, options,
                  &sink) != Status::ok)
    return -1;
  for (std::uint32_t z = 0; z < info.depth; ++z)
    if (engine.push_slice(volume.slice(z)) != Status::ok) return -1;
  if (engine.finish() != Status::ok) return -1;
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  *counters = engine.counters();
  return seconds;
}

}  // namespace mvox::bench
