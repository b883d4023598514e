#pragma once
// Test support for the command line's mesh options (--interpolate, --smooth, --decimate, the
// formats): a phantom stack to run on, a run that must succeed, and the check that a run moved
// each vertex along its own voxel edge only.
#include <cstddef>
#include <string>

#include "command_runner.h"
#include "read/ply/ply_reader.h"
#include "stl_reader.h"

namespace mvox::test {

// `mvox phantom NAME -o stack --size SIZE -q` in `dir`: an image stack at dir/stack.
void make_phantom_stack(const ScratchDirectory& dir, const std::string& name,
                        const std::string& size);

// Runs `mvox ARGUMENTS` in `dir`; fails the test unless it exits 0.
void expect_success(const std::string& arguments, const ScratchDirectory& dir);

// Fails the test unless `moved` has the vertices of `plain`, each changed in one coordinate at
// most, by less than `limit` (voxels): moved along its own edge. Returns how many moved.
std::size_t vertices_moved_along_edges(const PlyMesh& plain, const PlyMesh& moved, float limit);

// What --interpolate and --smooth promise of a mesh: `moved` has `plain`'s faces (more than
// 500 of them), more than half its vertices moved along their own edges (by under half a
// voxel), and is closed and consistently wound.
void expect_engines_faces_with_moved_vertices(const PlyMesh& plain, const PlyMesh& moved);

// Reads the STL file at `path`; fails the test unless every triangle corner is one of `mesh`'s
// vertices (STL repeats the indexed mesh's vertices by value). Returns the file.
StlFile expect_corners_among(const std::string& path, const PlyMesh& mesh);

}  // namespace mvox::test
