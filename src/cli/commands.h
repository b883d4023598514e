#pragma once
// The mvox subcommands. Each adds itself to the command line and runs when chosen; errors are
// thrown as mvox::Error and reported by main().
#include <CLI/CLI.hpp>

namespace mvox {

void add_extract_command(CLI::App& app);  // mvox extract INPUT... -t D -o mesh.ply
void add_demo_command(CLI::App& app);     // mvox demo: the built-in default, no files needed
void add_phantom_command(CLI::App& app);
void add_render_command(CLI::App& app);  // mvox render mesh.ply -o picture.png  // mvox phantom
                                         // NAME -o DIR: a phantom as an image stack

}  // namespace mvox
