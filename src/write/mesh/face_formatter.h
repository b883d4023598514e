#pragma once
// Faces formatted ahead of the file, by the thread that extracted them.
//
// With slab threads (pipeline/slab_extraction.h) only the worker whose turn it is writes into the
// mesh file; a worker ahead of it records its engine's output and formats it when its turn comes.
// For a format whose face records hold no vertex indices (STL: three positions and a normal a
// triangle), a record does not depend on where the slab's vertices land in the whole mesh, so the
// worker ahead can format its faces at once, in parallel with the writing one. The writer then
// only appends the bytes (MeshWriter::consume_formatted_faces). A FaceFormatter is that worker's
// copy of the writer's formatting: the same MeshWriter checks, placement, triangulation and
// records, into memory.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "write/mesh/formatted_records.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

class FaceFormatter : public MeshWriter {
 public:
  // Starts a slab whose engine numbered `shared_vertices` vertices it does not emit
  // (Engine::begin_slab): the vertex count starts there, so that the slab's local indices pass
  // MeshWriter's checks, and a refusal of an earlier slab is forgotten.
  void start_slab(std::uint64_t shared_vertices) { restart(shared_vertices); }
  // Where the next records go; borrowed until the next call.
  void format_into(FormattedRecords* records) { records_ = records; }
  // The most bytes of records one polygon can make (its triangles, when it is split).
  virtual std::size_t most_bytes_per_polygon() const = 0;

  const std::string& subject() const override { return subject_; }
  OutputFile* output_file() override { return nullptr; }

 protected:
  FaceFormatter(const MeshWriterOptions& options, Faces faces, Positions positions,
                std::string subject)
      : MeshWriter(options, faces, positions), subject_(std::move(subject)) {}
  // Throws (an internal error) before format_into() has given a target.
  FormattedRecords& records();

 private:
  void complete_file() override {}

  std::string subject_;
  FormattedRecords* records_ = nullptr;
};

}  // namespace mvox
