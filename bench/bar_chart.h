#pragma once
// A grouped bar chart as a PNG, drawn with OpenCV: two bars per group (the paper's Figure 16
// has T_c and T_v per dataset), each labelled with its value; the group's caption gives the saving
// 1 - ratio.
#include <string>
#include <vector>

namespace mvox::bench {

struct BarGroup {
  std::string label;
  double first = 0;   // e.g. T_c
  double second = 0;  // e.g. T_v
  double ratio = 0;   // second / first as the caption states it (e.g. a median of paired ratios)
};

// Writes the chart to `path` (the extension picks the format). Throws on a write error.
void draw_bar_chart(const std::string& path, const std::string& title,
                    const std::string& first_name, const std::string& second_name,
                    const std::vector<BarGroup>& groups);

}  // namespace mvox::bench
