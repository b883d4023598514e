#pragma once
// The mesh formats mvox writes, chosen by name (--format) or by the output's extension, and the
// writer for each.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "write/mesh/mesh_writer.h"

namespace mvox {

enum class MeshFormat : std::uint8_t { ply, ply_ascii, stl, obj };

// The choices for --format, for help and messages.
constexpr const char kMeshFormatChoices[] = "ply|ply-ascii|stl|obj";

// "ply", "ply-ascii", "stl" or "obj": the --format name.
const char* mesh_format_name(MeshFormat format);

// The format a --format name stands for, or nothing.
std::optional<MeshFormat> mesh_format_named(const std::string& name);

// The format a file name's extension implies, ignoring case: .ply (binary PLY), .stl, .obj; or
// nothing (another extension, none, or "-" for standard output).
std::optional<MeshFormat> mesh_format_of_path(const std::string& path);

// The batches every MeshWriter keeps, whatever the format: placed vertices and normals of a
// vertex batch (36 bytes each), a waiting polygon batch (32 each), and a run of 512 faces (for
// STL, a run of up to 32 KB of triangle records instead, in the file's own buffer): under
// 512 KiB for the engine's 4096-entry batches.
constexpr std::uint64_t kMeshWriterBatchBytes = 512 * 1024;

// The most memory a writer of `format` takes, whatever the mesh size: its write buffers
// (BufferedWriter, one per file and spool file: PLY keeps faces, and on a pipe vertices too, in
// spool files; STL keeps triangles in one on a pipe; each with a second buffer when
// `background_writes`), and the shared MeshWriter's batches.
std::uint64_t mesh_writer_working_bytes(MeshFormat format, bool background_writes = true);

// For a format whose writers have a FaceFormatter (MeshWriter::face_formatter: STL), the most
// bytes of records it makes of one polygon (FaceFormatter::most_bytes_per_polygon); else 0.
// For memory plans, made before any writer.
std::size_t formatted_bytes_per_polygon(MeshFormat format);
// For a text format, whose writers have a VertexTextFormatter (MeshWriter::vertex_text_formatter:
// OBJ, ASCII PLY), the most bytes it takes room for to format one vertex, with or without
// normals (VertexTextFormatter::most_bytes_per_vertex); else 0. For memory plans.
std::size_t formatted_bytes_per_vertex(MeshFormat format, bool normals);

// True when a writer of `format` with `options` needs every polygon's geometry from the engine
// (EngineOptions::polygon_geometry): STL and --triangulate.
bool mesh_writer_needs_geometry(MeshFormat format, const MeshWriterOptions& options);

// The head of a whole mesh file of `format` whose parts (MeshWriterOptions::part) hold
// `vertex_count` vertices and `face_count` faces: what one writer writes before the records of
// a regular file (PLY's header padded to its reserved size, STL's header and count, OBJ's
// comments). Throws mvox::Error when the format cannot count that many (STL).
std::string mesh_file_head(MeshFormat format, const MeshWriterOptions& options,
                           std::uint64_t vertex_count, std::uint64_t face_count);

// A writer of `format` to `path` ("-" for standard output). Throws mvox::Error as the writers do.
std::unique_ptr<MeshWriter> open_mesh_writer(const std::string& path, MeshFormat format,
                                             const MeshWriterOptions& options);

}  // namespace mvox
