#include "write/mesh/mesh_format.h"

#include <cctype>

#include "write/buffered_writer.h"
#include "write/mesh/float_texts.h"
#include "write/mesh/obj_writer.h"
#include "write/mesh/ply_writer.h"
#include "write/mesh/stl_writer.h"

namespace mvox {

const char* mesh_format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::ply: return "ply";
    case MeshFormat::ply_ascii: return "ply-ascii";
    case MeshFormat::stl: return "stl";
    case MeshFormat::obj: return "obj";
  }
  return "ply";
}

std::optional<MeshFormat> mesh_format_named(const std::string& name) {
  for (MeshFormat format :
       {MeshFormat::ply, MeshFormat::ply_ascii, MeshFormat::stl, MeshFormat::obj})
    if (name == mesh_format_name(format)) return format;
  return std::nullopt;
}

std::optional<MeshFormat> mesh_format_of_path(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  // A dot in a directory name, or a hidden file's leading dot, is not an extension.
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash) || dot == 0 ||
      dot == slash + 1)
    return std::nullopt;
  std::string extension = path.substr(dot + 1);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == "ply") return MeshFormat::ply;
  if (extension == "stl") return MeshFormat::stl;
  if (extension == "obj") return MeshFormat::obj;
  return std::nullopt;
}

std::uint64_t mesh_writer_working_bytes(MeshFormat format, bool background_writes) {
  const std::uint64_t files = format == MeshFormat::obj ? 1 : format == MeshFormat::stl ? 2 : 3;
  // Each file's buffer may have a second one while the first is written in the background
  // (buffered_writer.h).
  const std::uint64_t buffers = background_writes ? 2 : 1;
  // The text formats keep the texts of recent floats (float_texts.h).
  const bool text = format == MeshFormat::obj || format == MeshFormat::ply_ascii;
  return files * buffers * BufferedWriter::kBufferBytes + kMeshWriterBatchBytes +
         (text ? FloatTexts::kBytes : 0);
}

std::size_t formatted_bytes_per_polygon(MeshFormat format) {
  return format == MeshFormat::stl ? StlWriter::kMostBytesPerPolygon : 0;
}

std::size_t formatted_bytes_per_vertex(MeshFormat format, bool normals) {
  switch (format) {
    case MeshFormat::obj: return ObjWriter::most_vertex_text_bytes(normals);
    case MeshFormat::ply_ascii: return PlyWriter::most_vertex_text_bytes(normals);
    case MeshFormat::ply:
    case MeshFormat::stl: return 0;
  }
  return 0;
}

bool mesh_writer_needs_geometry(MeshFormat format, const MeshWriterOptions& options) {
  return format == MeshFormat::stl || options.triangulate;
}

namespace {

PlyWriterOptions ply_options(MeshFormat format, const MeshWriterOptions& options) {
  PlyWriterOptions ply;
  static_cast<MeshWriterOptions&>(ply) = options;
  ply.format = format == MeshFormat::ply_ascii ? PlyFormat::ascii : PlyFormat::binary_little_endian;
  return ply;
}

}  // namespace

std::string mesh_file_head(MeshFormat format, const MeshWriterOptions& options,
                           std::uint64_t vertex_count, std::uint64_t face_count) {
  switch (format) {
    case MeshFormat::stl: return StlWriter::head(options, face_count);
    case MeshFormat::obj: return ObjWriter::head(options);
    case MeshFormat::ply:
    case MeshFormat::ply_ascii: break;
  }
  return PlyWriter::head(ply_options(format, options), vertex_count, face_count);
}

std::unique_ptr<MeshWriter> open_mesh_writer(const std::string& path, MeshFormat format,
                                             const MeshWriterOptions& options) {
  switch (format) {
    case MeshFormat::stl: return std::make_unique<StlWriter>(path, options);
    case MeshFormat::obj: return std::make_unique<ObjWriter>(path, options);
    case MeshFormat::ply:
    case MeshFormat::ply_ascii: break;
  }
  return std::make_unique<PlyWriter>(path, ply_options(format, options));
}

}  // namespace mvox
