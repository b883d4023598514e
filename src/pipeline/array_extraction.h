#pragma once
// One extraction into arrays in memory: what `mvox extract -o mesh.ply` writes, vertex for
// vertex and face for face, but kept as MeshArrays (write/mesh/mesh_arrays.h). The Python
// module's mvox.extract and mvox.extract_file run this.
#include <string>

#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "write/mesh/mesh_arrays.h"
#include "write/mesh/world_transform.h"

namespace mvox {

struct ArrayExtractionOptions {
  double threshold = 0;  // in sample units: a voxel is inner when its value >= threshold
  EngineOptions engine;  // method, engine kind, surface rule
  WorldTransform placement;
  bool triangulate = false;  // faces as triangles (polygon_triangulation.h), as --triangulate
  bool normals = false;      // gradient normals per vertex, as --normals
  // Above 1: slabs extracted on that many threads (slab_extraction.h), the same arrays. Pays
  // where reading does (files decoded by each thread for its own slabs): in memory, the arrays
  // are built by one thread in order, which two workers do not outrun.
  unsigned threads = 1;
};

struct ArrayExtraction {
  MeshArrays mesh;
  EngineCounters counters;
};

// Streams every slice of `source` through the engine into arrays. Throws mvox::Error naming
// `label` (the input, or the calling function) when the engine refuses the source or the mesh
// cannot be built. Memory: the engine's workspace and, with normals, four slices, plus the
// arrays; with threads, that per worker and its recorded output (slab_pipeline_bytes()).
ArrayExtraction extract_to_arrays(SliceSource& source, const ArrayExtractionOptions& options,
                                  const std::string& label);

}  // namespace mvox
