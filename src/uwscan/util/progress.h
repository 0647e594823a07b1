// A progress bar on stderr, drawn only when stderr is a terminal (and the
// caller did not ask for quiet), redrawn at most 10 times a second.
#pragma once

#include <chrono>
#include <string>

namespace uwscan {

class ProgressBar {
 public:
  ProgressBar(std::string label, long total, bool enabled = true);
  ~ProgressBar();
  void Update(long done);
  void Finish();  // final redraw and newline
  bool enabled() const { return enabled_; }

 private:
  void Draw(long done);

  std::string label_;
  long total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace uwscan
