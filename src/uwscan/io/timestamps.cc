#include "uwscan/io/timestamps.h"

#include <fmt/format.h>

#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan {

void CheckTimestampsInSeconds(const std::vector<double>& times_s, const std::string& context) {
  if (times_s.size() < 2) return;
  std::vector<double> steps;
  for (size_t i = 1; i < times_s.size(); ++i) steps.push_back(times_s[i] - times_s[i - 1]);
  const double step = Median(steps);
  UWS_CHECK(step <= kMaxMedianTimestampStepS, context, ": timestamps step by ",
            fmt::format("{:.6g}", step), " s from one to the next (median): they are in seconds",
            step > 1e6   ? ", and these look like nanoseconds (divide by 1e9)"
            : step > 1e3 ? ", and these look like microseconds (divide by 1e6)"
                         : "",
            "; more than ", kMaxMedianTimestampStepS, " s apart they are no scan");
}

}  // namespace uwscan
