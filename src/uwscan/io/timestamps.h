// Timestamps in seconds, as frames.csv and TUM files have them.
#pragma once

#include <string>
#include <vector>

namespace uwscan {

// The median step between consecutive timestamps above which they are
// refused: frames or poses more than this apart are no scan.
constexpr double kMaxMedianTimestampStepS = 600.0;

// Throws uwscan::Error, naming `context`, when increasing timestamps step by
// more than kMaxMedianTimestampStepS (median): they are then in another unit
// (a camera's or a bag exporter's nanoseconds or microseconds), which the
// message names. Passes epoch seconds and a still camera's minutes.
void CheckTimestampsInSeconds(const std::vector<double>& times_s, const std::string& context);

}  // namespace uwscan
