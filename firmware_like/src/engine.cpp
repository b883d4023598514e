// Placeholder until the engine lands; keeps the skeleton building.
#include "mvox/engine.h"

namespace mvox {

std::size_t engine_workspace_bytes(std::uint32_t, std::uint32_t, const EngineOptions&) { return 0; }
Status Engine::init(void*, std::size_t, std::uint32_t, std::uint32_t, double, const EngineOptions&,
                    PolygonSink*) {
  return Status::invalid_argument;
}
Status Engine::push_slice(const SliceView&) { return Status::not_initialised; }
Status Engine::finish() { return Status::not_initialised; }

}  // namespace mvox
