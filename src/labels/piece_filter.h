#pragma once
// Connected pieces of a spooled surface (--largest, --min-faces): which polygons form one
// piece, found in a pass over the spool, then a second pass that writes only the pieces kept,
// vertices renumbered in order.
//
// Memory grows with the number of pieces, not the surface: polygons refer only to vertices of
// their own layer of cubes (mvox/mesh.h), so the vertex-to-piece map is a ring over the most
// recent vertices (a power of two, at least 8 per slice pixel, checked), and the pieces form a
// union-find whose size is the number of piece starts (a new piece, or a branch of one that
// later joins it). Each vertex's piece, once it leaves the ring, goes to a scratch file (4 bytes
// a vertex, on disk) that the second pass reads back in order.
#include <cstdint>
#include <vector>

#include "labels/label_spool.h"
#include "mvox/polygon_sink.h"

namespace mvox {

struct PieceRule {
  bool largest = false;        // keep only the piece with the most faces (the first, on a tie)
  std::uint64_t min_faces = 0;  // drop pieces of fewer faces (polygons)
  bool active() const { return largest || min_faces > 0; }
};

struct PieceCounts {
  std::uint64_t pieces = 0;       // connected pieces of the surface
  std::uint64_t pieces_kept = 0;
  std::uint64_t polygons_kept = 0;
  std::uint64_t vertices_kept = 0;
  std::uint64_t piece_starts = 0;  // union-find entries: the memory that grows (16 bytes each)
};

// The memory write_kept_pieces takes besides the pieces (16 bytes per piece start): its vertex
// ring for slices of `slice_pixels` pixels, one pass at a time.
std::uint64_t piece_filter_bytes(std::uint64_t slice_pixels);

// Writes `label`'s spooled surface into `sink`, keeping the pieces `rule` keeps. `slice_pixels`
// (width * height) sizes the ring. Throws mvox::Error (the spool's read errors, or a polygon
// referring further back than the ring, which the engine never does); returns the sink's first
// refusal, else Status::ok.
Status write_kept_pieces(LabelSpool& spool, std::uint32_t label, std::uint64_t slice_pixels,
                         const PieceRule& rule, const std::string& scratch_directory,
                         PolygonSink& sink, PieceCounts* counts);

}  // namespace mvox
