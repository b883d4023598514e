#include "stats_json.h"

#include <cstdio>
#include <sstream>

namespace mvox {

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
          out += escaped;
        } else {
          out += static_cast<char>(c);
        }
    }
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
      << "  \"inner_voxels\": " << c.inner_voxels << ",\n"
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
      << "\n"
      << "}\n";
  return out.str();
}

}  // namespace mvox
