#pragma once
// Operating errors of the core, reported as values (the core has no exceptions).
#include <cstdint>

namespace mvox {

enum class [[nodiscard]] Status : std::uint8_t{
    ok = 0,
    invalid_argument,       // a null pointer, zero size or an option out of range
    workspace_misaligned,   // workspace pointer not aligned to kWorkspaceAlignment
    workspace_too_small,    // fewer bytes than engine_workspace_bytes() asks for
    not_initialised,        // push_slice()/finish() before a successful init()
    slice_size_mismatch,    // a slice whose width or height differs from init()
    already_finished,       // push_slice()/finish() after finish()
    sink_refused,           // the polygon sink returned an error; the engine stopped
    vertex_index_overflow,  // no longer returned (indices go on past 2^32, mesh.h); keeps its
                            // number
};

// A short English description, for messages ("workspace too small").
const char* status_message(Status status);

}  // namespace mvox
