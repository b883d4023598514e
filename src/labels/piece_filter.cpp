#include "labels/piece_filter.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>

#include "error.h"
#include "write/scratch_file.h"

namespace mvox {
namespace {

constexpr std::uint32_t kNoPiece = std::numeric_limits<std::uint32_t>::max();

std::size_t ring_size(std::uint64_t slice_pixels) {
  std::size_t size = 1 << 16;
  while (size < 8 * slice_pixels) size <<= 1;
  return size;
}

// Union-find over piece starts, with the faces of each.
class Pieces {
 public:
  std::uint32_t add() {
    // Piece numbers are 32-bit, kNoPiece the last: a surface of four billion starts is refused.
    if (parent_.size() >= kNoPiece)
      throw Error("--largest/--min-faces", "more than 4294967294 piece starts");
    parent_.push_back(static_cast<std::uint32_t>(parent_.size()));
    faces_.push_back(0);
    return parent_.back();
  }
  std::uint32_t find(std::uint32_t piece) {
    while (parent_[piece] != piece) {
      parent_[piece] = parent_[parent_[piece]];
      piece = parent_[piece];
    }
    return piece;
  }
  std::uint32_t join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return a;
    if (b < a) std::swap(a, b);  // the earlier start stays the root: the same on every run
    parent_[b] = a;
    faces_[a] += faces_[b];
    return a;
  }
  void add_face(std::uint32_t piece) { ++faces_[find(piece)]; }
  std::uint64_t faces(std::uint32_t root) const { return faces_[root]; }
  std::size_t size() const { return parent_.size(); }

 private:
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint64_t> faces_;
};

// A ring of the most recent vertices' values, addressed by their index modulo 2^32.
class VertexRing {
 public:
  explicit VertexRing(std::size_t size) : values_(size, kNoPiece), mask_(size - 1) {}
  std::uint32_t& at(std::uint32_t index) { return values_[index & mask_]; }
  std::size_t size() const { return values_.size(); }

 private:
  std::vector<std::uint32_t> values_;
  std::size_t mask_;
};

// Pass 1: the pieces. Vertices leaving the ring go to `pieces_file` with their piece.
class PieceFinder final : public PolygonSink {
 public:
  PieceFinder(std::size_t ring, ScratchFile& pieces_file, const std::string& subject)
      : ring_(ring), file_(pieces_file), subject_(subject) {}

  Status consume_vertices(const Vertex*, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i) {
      if (vertices_ >= ring_.size()) evict(static_cast<std::uint32_t>(vertices_ - ring_.size()));
      ring_.at(static_cast<std::uint32_t>(vertices_)) = kNoPiece;
      ++vertices_;
    }
    return Status::ok;
  }
  Status consume_polygons(const Polygon* polygons, std::size_t count) override {
    for (std::size_t p = 0; p < count; ++p) {
      const Polygon& polygon = polygons[p];
      std::uint32_t piece = kNoPiece;
      for (int k = 0; k < polygon.vertex_count; ++k) {
        const std::uint32_t index = polygon.vertices[k];
        check_reach(index);
        const std::uint32_t of_vertex = ring_.at(index);
        if (of_vertex == kNoPiece) continue;
        piece = piece == kNoPiece ? pieces_.find(of_vertex) : pieces_.join(piece, of_vertex);
      }
      if (piece == kNoPiece) piece = pieces_.add();
      for (int k = 0; k < polygon.vertex_count; ++k) {
        std::uint32_t& of_vertex = ring_.at(polygon.vertices[k]);
        if (of_vertex == kNoPiece) of_vertex = piece;
      }
      pieces_.add_face(piece);
    }
    return Status::ok;
  }
  Status consume_polygon_geometry(const PolygonGeometry*, std::size_t) override {
    return Status::ok;
  }

  // After the last record: the vertices still in the ring go to the file too.
  void finish() {
    const std::uint64_t first = vertices_ > ring_.size() ? vertices_ - ring_.size() : 0;
    for (std::uint64_t v = first; v < vertices_; ++v) evict(static_cast<std::uint32_t>(v));
  }
  Pieces& pieces() { return pieces_; }

 private:
  void evict(std::uint32_t index) {
    const std::uint32_t piece = ring_.at(index);
    file_.write(&piece, sizeof piece);
  }
  void check_reach(std::uint32_t index) const {
    const std::uint32_t back = static_cast<std::uint32_t>(vertices_ - 1) - index;
    if (vertices_ == 0 || back >= ring_.size())
      throw Error(subject_, "internal error: a polygon refers to a vertex " +
                                std::to_string(back) + " back, beyond the " +
                                std::to_string(ring_.size()) + " kept for --largest/--min-faces");
  }

  VertexRing ring_;
  ScratchFile& file_;
  std::string subject_;
  Pieces pieces_;
  std::uint64_t vertices_ = 0;
};

// Pass 2: the kept pieces into `sink`, vertices renumbered in order.
class PieceWriter final : public PolygonSink {
 public:
  PieceWriter(std::size_t ring, ScratchFile& pieces_file, Pieces& pieces,
              const std::vector<bool>& kept_roots, PolygonSink& sink, PieceCounts& counts)
      : ring_(ring), file_(pieces_file), pieces_(pieces), kept_(kept_roots), sink_(sink),
        counts_(counts) {}

  Status consume_vertices(const Vertex* vertices, std::size_t count) override {
    piece_of_.resize(count);
    file_.read_at(vertices_ * sizeof(std::uint32_t), piece_of_.data(), count * sizeof(std::uint32_t));
    kept_vertices_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t piece = piece_of_[i];
      const bool keep = piece != kNoPiece && kept_[pieces_.find(piece)];
      // New indices are 32-bit with kNoPiece marking a dropped vertex: PLY and STL cannot hold
      // more vertices than that anyway.
      if (keep && written_ >= kNoPiece)
        throw Error("--largest/--min-faces", "more than 4294967294 vertices kept");
      ring_.at(static_cast<std::uint32_t>(vertices_ + i)) =
          keep ? static_cast<std::uint32_t>(written_++) : kNoPiece;
      if (keep) kept_vertices_.push_back(vertices[i]);
    }
    vertices_ += count;
    counts_.vertices_kept += kept_vertices_.size();
    if (kept_vertices_.empty()) return Status::ok;
    return sink_.consume_vertices(kept_vertices_.data(), kept_vertices_.size());
  }
  Status consume_polygons(const Polygon* polygons, std::size_t count) override {
    kept_polygons_.clear();
    polygon_kept_.assign(count, false);
    for (std::size_t p = 0; p < count; ++p) {
      Polygon moved = polygons[p];
      // One piece per polygon: its first vertex says which.
      if (ring_.at(moved.vertices[0]) == kNoPiece) continue;
      for (int k = 0; k < moved.vertex_count; ++k) moved.vertices[k] = ring_.at(moved.vertices[k]);
      kept_polygons_.push_back(moved);
      polygon_kept_[p] = true;
    }
    counts_.polygons_kept += kept_polygons_.size();
    if (kept_polygons_.empty()) return Status::ok;
    return sink_.consume_polygons(kept_polygons_.data(), kept_polygons_.size());
  }
  // Geometry follows its polygon batch (EngineOptions::polygon_geometry): the same ones kept.
  Status consume_polygon_geometry(const PolygonGeometry* polygons, std::size_t count) override {
    kept_geometry_.clear();
    for (std::size_t p = 0; p < count && p < polygon_kept_.size(); ++p)
      if (polygon_kept_[p]) kept_geometry_.push_back(polygons[p]);
    if (kept_geometry_.empty()) return Status::ok;
    return sink_.consume_polygon_geometry(kept_geometry_.data(), kept_geometry_.size());
  }

 private:
  VertexRing ring_;  // whole new index of each recent vertex (modulo 2^32), or kNoPiece
  ScratchFile& file_;
  Pieces& pieces_;
  const std::vector<bool>& kept_;
  PolygonSink& sink_;
  PieceCounts& counts_;
  std::uint64_t vertices_ = 0;
  std::uint64_t written_ = 0;
  std::vector<std::uint32_t> piece_of_;
  std::vector<Vertex> kept_vertices_;
  std::vector<Polygon> kept_polygons_;
  std::vector<bool> polygon_kept_;
  std::vector<PolygonGeometry> kept_geometry_;
};

}  // namespace

std::uint64_t piece_filter_bytes(std::uint64_t slice_pixels) {
  return ring_size(slice_pixels) * sizeof(std::uint32_t);
}

Status write_kept_pieces(LabelSpool& spool, std::uint32_t label, std::uint64_t slice_pixels,
                         const PieceRule& rule, const std::string& scratch_directory,
                         PolygonSink& sink, PieceCounts* counts) {
  *counts = PieceCounts();
  const std::size_t ring = ring_size(slice_pixels);
  ScratchFile pieces_file(scratch_directory, "--largest/--min-faces");
  Pieces pieces;
  {
    // Pass 1; its ring goes before pass 2 makes its own.
    PieceFinder finder(ring, pieces_file, "--largest/--min-faces");
    const Status status = spool.replay(label, finder);
    if (status != Status::ok) return status;
    finder.finish();
    pieces = std::move(finder.pieces());
  }
  counts->piece_starts = pieces.size();

  std::vector<bool> kept(pieces.size(), false);
  std::uint32_t largest = kNoPiece;
  for (std::uint32_t piece = 0; piece < static_cast<std::uint32_t>(pieces.size()); ++piece) {
    if (pieces.find(piece) != piece) continue;
    ++counts->pieces;
    if (largest == kNoPiece || pieces.faces(piece) > pieces.faces(largest)) largest = piece;
    kept[piece] = pieces.faces(piece) >= rule.min_faces;
  }
  if (rule.largest)
    for (std::uint32_t piece = 0; piece < static_cast<std::uint32_t>(pieces.size()); ++piece)
      kept[piece] = kept[piece] && piece == largest;
  for (std::uint32_t piece = 0; piece < static_cast<std::uint32_t>(pieces.size()); ++piece)
    counts->pieces_kept += kept[piece] && pieces.find(piece) == piece;

  PieceWriter writer(ring, pieces_file, pieces, kept, sink, *counts);
  return spool.replay(label, writer);
}

}  // namespace mvox
