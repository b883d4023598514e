#pragma once
// Vertex lines formatted ahead of the file, by the thread that placed the vertices.
//
// The text formats' vertex lines (OBJ "v" and "vn", ASCII PLY) hold no vertex index, so a slab
// worker ahead of its turn (pipeline/slab_write_turns.h) can format them at once, in parallel
// with the writing worker, as STL's workers format their triangles (face_formatter.h). The
// writer then only appends the bytes (MeshWriter::consume_formatted_vertices). Making the text
// of a float was most of the time of writing those formats.
#include <cstddef>

#include "write/mesh/float_texts.h"
#include "write/mesh/formatted_records.h"
#include "write/mesh/vertex_placement.h"

namespace mvox {

class VertexTextFormatter {
 public:
  virtual ~VertexTextFormatter() = default;
  // The most bytes formatting one vertex takes room for (its lines, with the room
  // FloatTexts::put() writes into).
  virtual std::size_t most_bytes_per_vertex() const = 0;
  // Appends the lines of `count` vertices, placed by the writer's placement: the very bytes the
  // writer would write for them.
  virtual void format(const WorldVertex* vertices, std::size_t count,
                      FormattedRecords& records) = 0;
};

// A writer's vertex lines made by its own function (the one it writes the file with), with
// floats' texts of their own: what OBJ and ASCII PLY give their slab workers.
class VertexLines final : public VertexTextFormatter {
 public:
  using Put = void (*)(FormattedRecords& records, const WorldVertex* vertices, std::size_t count,
                       bool normals, FloatTexts& texts);
  VertexLines(Put put, bool normals, std::size_t most_bytes_per_vertex)
      : put_(put), normals_(normals), most_bytes_(most_bytes_per_vertex) {}
  std::size_t most_bytes_per_vertex() const override { return most_bytes_; }
  void format(const WorldVertex* vertices, std::size_t count, FormattedRecords& records) override {
    put_(records, vertices, count, normals_, texts_);
  }

 private:
  Put put_;
  bool normals_;
  std::size_t most_bytes_;
  FloatTexts texts_;
};

}  // namespace mvox
