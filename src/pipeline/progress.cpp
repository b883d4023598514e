#include "pipeline/progress.h"

#include <unistd.h>

#include <cstdio>

namespace mvox {
namespace {

std::string clock_text(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

}  // namespace

bool ProgressLine::stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

ProgressLine::ProgressLine(std::string label, std::uint32_t total_slices, bool enabled)
    : label_(std::move(label)),
      total_(total_slices),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_),
      last_look_(start_) {}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::update(std::uint32_t slices_done) {
  if (!enabled_) return;
  const bool last = slices_done == total_;
  if (!last && slices_done - looked_at_ < stride_) return;
  looked_at_ = slices_done;
  const auto now = std::chrono::steady_clock::now();
  const auto since_look = now - last_look_;
  last_look_ = now;
  // At most 1024 slices between readings, and back to every slice when slices slow down, so
  // that a volume whose slices come slowly after a fast start (a pipe) still shows its progress.
  if (since_look < std::chrono::milliseconds(1) && stride_ < 1024) stride_ *= 2;
  if (since_look > std::chrono::milliseconds(10)) stride_ = 1;
  // Redraw at most ten times a second: a terminal is slower than the engine.
  if (drawn_ && !last && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? slices_done / elapsed : 0;
  constexpr int kBarWidth = 24;
  std::string bar;
  std::string left;
  if (total_ > 0) {
    const int filled = static_cast<int>(kBarWidth * static_cast<double>(slices_done) / total_);
    bar = "[" + std::string(filled, '#') + std::string(kBarWidth - filled, '.') + "] ";
    if (rate > 0) left = "  " + clock_text((total_ - slices_done) / rate) + " left";
  }
  std::fprintf(stderr, "\r%s %s%u/%u slices  %.0f slices/s%s\033[K", label_.c_str(), bar.c_str(),
               slices_done, total_, rate, left.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressLine::finish() {
  if (!drawn_) return;
  std::fputc('\n', stderr);
  drawn_ = false;
}

}  // namespace mvox
