#include "bar_chart.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace mvox::bench {
namespace {

const cv::Scalar kFirstColour(70, 110, 200);   // BGR: warm brown-orange for the baseline
const cv::Scalar kSecondColour(180, 120, 40);  // BGR: blue for marching voxels
const cv::Scalar kInk(40, 40, 40);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

void text(cv::Mat& image, const std::string& words, cv::Point at, double scale, bool centred) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(words, kFont, scale, 1, &baseline);
  if (centred) at.x -= size.width / 2;
  cv::putText(image, words, at, kFont, scale, kInk, 1, cv::LINE_AA);
}

std::string number(double value, const char* format) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace

void draw_bar_chart(const std::string& path, const std::string& title,
                    const std::string& first_name, const std::string& second_name,
                    const std::vector<BarGroup>& groups) {
  const int width = 760, height = 420, left = 70, right = 20, top = 70, bottom = 60;
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  double highest = 0;
  for (const BarGroup& g : groups) highest = std::max({highest, g.first, g.second});
  highest = highest > 0 ? highest * 1.15 : 1;
  const int plot_height = height - top - bottom;
  auto y_of = [&](double value) { return top + plot_height - int(value / highest * plot_height); };

  text(image, title, {width / 2, 28}, 0.6, true);
  // Legend.
  cv::rectangle(image, {left, 42}, {left + 14, 56}, kFirstColour, cv::FILLED);
  text(image, first_name, {left + 20, 55}, 0.5, false);
  cv::rectangle(image, {left + 240, 42}, {left + 254, 56}, kSecondColour, cv::FILLED);
  text(image, second_name, {left + 260, 55}, 0.5, false);
  // Axis with a few gridlines.
  for (int i = 0; i <= 4; ++i) {
    const double value = highest / 1.15 * i / 4;
    const int y = y_of(value);
    cv::line(image, {left, y}, {width - right, y}, cv::Scalar(225, 225, 225), 1);
    text(image, number(value, "%.0f"), {left - 40, y + 5}, 0.45, false);
  }
  cv::line(image, {left, top}, {left, top + plot_height}, kInk, 1);
  cv::line(image, {left, top + plot_height}, {width - right, top + plot_height}, kInk, 1);

  const int slot = (width - left - right) / std::max<int>(1, int(groups.size()));
  const int bar = std::min(70, slot / 3);
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const BarGroup& g = groups[i];
    const int centre = left + slot * int(i) + slot / 2;
    const int base = top + plot_height;
    cv::rectangle(image, {centre - bar - 4, y_of(g.first)}, {centre - 4, base}, kFirstColour,
                  cv::FILLED);
    cv::rectangle(image, {centre + 4, y_of(g.second)}, {centre + bar + 4, base}, kSecondColour,
                  cv::FILLED);
    text(image, number(g.first, "%.0f"), {centre - bar / 2 - 4, y_of(g.first) - 6}, 0.45, true);
    text(image, number(g.second, "%.0f"), {centre + bar / 2 + 4, y_of(g.second) - 6}, 0.45, true);
    const double saving = (1 - g.ratio) * 100;
    text(image, g.label + "  (" + number(saving, "%.0f") + "% less)", {centre, base + 25}, 0.5,
         true);
  }
  if (!cv::imwrite(path, image)) throw std::runtime_error(path + ": cannot write the chart");
}

}  // namespace mvox::bench
