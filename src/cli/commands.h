#pragma once
// The mvox subcommands. Each adds itself to the command line and runs when chosen; errors are
// thrown as mvox::Error and reported by main().
#include <CLI/CLI.hpp>
#include <functional>

#include "mvox/slice_source.h"

namespace mvox {

struct MeshJob;
// What runs the job `extract` has read its options and opened its input for: run_mesh_job()
// when empty; mvox-mpi runs it on many processes.
using ExtractRunner = std::function<void(SliceSource& source, const MeshJob& job)>;

// mvox extract INPUT... -t D -o mesh.ply
void add_extract_command(CLI::App& app, ExtractRunner runner = {});
void add_demo_command(CLI::App& app);     // mvox demo: the built-in default, no files needed
void add_phantom_command(CLI::App& app);  // mvox phantom NAME -o DIR: a phantom as a stack
void add_render_command(CLI::App& app);   // mvox render mesh.ply -o picture.png

}  // namespace mvox
