#include "uwscan/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "uwscan/util/stopwatch.h"

namespace uwscan {

ProgressBar::ProgressBar(std::string label, long total, bool enabled)
    : label_(std::move(label)),
      total_(std::max(total, 1L)),
      enabled_(enabled && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && !finished_) std::fputc('\n', stderr);
}

void ProgressBar::Update(long done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && done < total_) return;
  last_draw_ = now;
  Draw(done);
}

void ProgressBar::Finish() {
  if (!enabled_ || finished_) return;
  Draw(total_);
  std::fputc('\n', stderr);
  finished_ = true;
}

void ProgressBar::Draw(long done) {
  constexpr int kWidth = 30;
  const double fraction = std::clamp(static_cast<double>(done) / total_, 0.0, 1.0);
  const int filled = static_cast<int>(fraction * kWidth);
  const double elapsed = SecondsSince(start_);
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %ld/%ld %.1f/s ", label_.c_str(), filled,
               "##############################", kWidth - filled, "", done, total_, rate);
  std::fflush(stderr);
}

}  // namespace uwscan
