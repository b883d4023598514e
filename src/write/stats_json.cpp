#include "write/stats_json.h"

#include <cstdio>
#include <sstream>
#include <string_view>

namespace mvox {

namespace {

// The length of the well-formed UTF-8 sequence at the start of `text` (1 to 4), or 0 when it
// does not start with one: a stray continuation byte, an overlong form, a surrogate, a code
// point past U+10FFFF, or a sequence cut short (Unicode's table 3-7).
std::size_t utf8_sequence_length(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xbf;  // the second byte's range
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    if (lead == 0xe0) low = 0xa0;   // overlong
    if (lead == 0xed) high = 0x9f;  // surrogates
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    if (lead == 0xf0) low = 0x90;   // overlong
    if (lead == 0xf4) high = 0x8f;  // past U+10FFFF
  } else {
    return 0;
  }
  if (text.size() < length || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i)
    if (byte(i) < 0x80 || byte(i) > 0xbf) return 0;
  return length;
}

}  // namespace

std::string json_string(const std::string& text) {
  std::string out = "\"";
  std::string_view rest = text;
  while (!rest.empty()) {
    const std::size_t length = utf8_sequence_length(rest);
    if (length == 0) {
      // A byte that is not UTF-8 (a file name in Latin-1, say) would make the report invalid
      // JSON: it becomes U+FFFD, the replacement character, one per byte.
      out += "\xef\xbf\xbd";
      rest.remove_prefix(1);
      continue;
    }
    const auto c = static_cast<unsigned char>(rest[0]);
    if (c == '"') {
      out += "\\\"";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (c < 0x20 || c == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      out.append(rest.data(), length);
    }
    rest.remove_prefix(length);
  }
  return out + "\"";
}

namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

}  // namespace

std::string run_report_json(const RunReport& r) {
  const EngineCounters& c = r.result.counters;
  const PhaseTimes& t = r.result.times;
  const double voxels = double(r.volume.width) * r.volume.height * double(c.slices);
  std::ostringstream out;
  out << "{\n"
      << "  \"input\": " << json_string(r.input) << ",\n"
      << "  \"output\": " << json_string(r.output) << ",\n"
      << "  \"format\": " << json_string(r.format) << ",\n"
      << "  \"image\": " << json_string(r.image) << ",\n"
      << "  \"dimensions\": [" << r.volume.width << ", " << r.volume.height << ", " << c.slices
      << "],\n"
      << "  \"sample_type\": " << json_string(sample_type_name(r.volume.type)) << ",\n"
      << "  \"spacing\": [" << number(r.volume.spacing[0]) << ", " << number(r.volume.spacing[1])
      << ", " << number(r.volume.spacing[2]) << "],\n"
      << "  \"origin\": [" << number(r.volume.origin[0]) << ", " << number(r.volume.origin[1])
      << ", " << number(r.volume.origin[2]) << "],\n"
      << "  \"axes\": [";
  for (int a = 0; a < 3; ++a)
    out << (a > 0 ? ", " : "") << "[" << number(r.volume.axes[a][0]) << ", "
        << number(r.volume.axes[a][1]) << ", " << number(r.volume.axes[a][2]) << "]";
  out << "],\n"
      << "  \"threshold\": " << number(r.threshold) << ",\n"
      << "  \"method\": " << json_string(r.method) << ",\n"
      << "  \"engine\": " << json_string(r.engine) << ",\n"
      << "  \"surface\": " << json_string(r.surface) << ",\n"
      << "  \"interpolated\": " << (r.interpolated ? "true" : "false") << ",\n"
      << "  \"smooth_iterations\": " << r.smooth_iterations << ",\n";
  if (r.decimation) {
    const DecimationCounts& d = r.result.decimation;
    out << "  \"decimation\": {\"ratio\": " << number(r.decimation->ratio)
        << ", \"max_error_voxels\": " << number(r.decimation->max_error_voxels)
        << ", \"triangles_in\": " << d.triangles_in << ", \"triangles_out\": " << d.triangles_out
        << ", \"vertices_out\": " << d.vertices_out << "},\n";
  }
  if (r.piece_rule) {
    const PieceCounts& p = r.pieces;
    out << "  \"pieces\": {\"largest\": " << (r.piece_rule->largest ? "true" : "false")
        << ", \"min_faces\": " << r.piece_rule->min_faces << ", \"pieces\": " << p.pieces
        << ", \"pieces_kept\": " << p.pieces_kept << ", \"polygons_kept\": " << p.polygons_kept
        << ", \"vertices_kept\": " << p.vertices_kept << ", \"piece_starts\": " << p.piece_starts
        << "},\n";
  }
  out << "  \"inner_voxels\": " << c.inner_voxels << ",\n"
      << "  \"vertices\": " << c.vertices << ",\n"
      << "  \"polygons\": " << c.polygons << ",\n"
      << "  \"polygons_by_size\": {";
  for (int size = 3; size <= kMaxPolygonVertices; ++size)
    out << (size > 3 ? ", " : "") << "\"" << size << "\": " << c.polygons_by_size[size];
  out << "},\n"
      << "  \"faces_written\": " << r.faces_written << ",\n"
      << "  \"time_seconds\": {\"read\": " << number(t.read_s)
      << ", \"extract\": " << number(t.extract_s) << ", \"write\": " << number(t.write_s)
      << ", \"render\": " << number(t.render_s) << ", \"total\": " << number(t.total_s) << "},\n"
      << "  \"extract_mvoxels_per_second\": "
      << number(t.extract_s > 0 ? voxels / t.extract_s / 1e6 : 0) << ",\n"
      << "  \"render\": {\"triangles_drawn\": " << r.render.triangles_drawn
      << ", \"triangles_culled\": " << r.render.triangles_culled
      << ", \"triangles_hidden\": " << r.render.triangles_hidden
      << ", \"fragments_written\": " << r.render.fragments_written << "},\n"
      << "  \"engine_workspace_bytes\": " << r.result.workspace_bytes << ",\n"
      << "  \"memory_plan\": {\"parts\": [";
  for (std::size_t i = 0; i < r.memory_plan.items.size(); ++i)
    out << (i > 0 ? ", " : "") << "{\"name\": " << json_string(r.memory_plan.items[i].name)
        << ", \"bytes\": " << r.memory_plan.items[i].bytes << "}";
  out << "], \"job_bytes\": " << r.memory_plan.job_bytes()
      << ", \"process_bytes\": " << r.memory_plan.process_bytes
      << ", \"total_bytes\": " << r.memory_plan.total_bytes()
      << ", \"budget_bytes\": " << r.memory_budget.bytes
      << ", \"budget_source\": " << json_string(r.memory_budget.source) << "},\n"
      << "  \"start_memory_bytes\": " << r.start_memory_bytes << ",\n"
      << "  \"peak_memory_bytes\": " << r.peak_memory_bytes << ",\n"
      << "  \"job_memory_bytes\": "
      << (r.peak_memory_bytes > r.start_memory_bytes ? r.peak_memory_bytes - r.start_memory_bytes
                                                     : 0)
      << ",\n"
      << "  \"slab_chunks_taken\": " << r.result.slab_chunks_taken << "\n"
      << "}\n";
  return out.str();
}

}  // namespace mvox
