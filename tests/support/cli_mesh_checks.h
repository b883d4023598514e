#pragma once
// Test support for the command line's mesh options (--interpolate, --smooth, --decimate, the
// formats): a phantom stack to run on, a run that must succeed, and the check that a run moved
// each vertex along its own voxel edge only.
#include <cstddef>
#include <string>

#include "command_runner.h"
#include "read/ply/ply_reader.h"

namespace mvox::test {

// `mvox phantom NAME -o stack --size SIZE -q` in `dir`: an image stack at dir/stack.
void make_phantom_stack(const ScratchDirectory& dir, const std::string& name,
                        const std::string& size);

// Runs `mvox ARGUMENTS` in `dir`; fails the test unless it exits 0.
void expect_success(const std::string& arguments, const ScratchDirectory& dir);

// Fails the test unless `moved` has the vertices of `plain`, each changed in one coordinate at
// most, by less than `limit` (voxels): moved along its own edge. Returns how many moved.
std::size_t vertices_moved_along_edges(const PlyMesh& plain, const PlyMesh& moved, float limit);

}  // namespace mvox::test
