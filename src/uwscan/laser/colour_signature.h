// The laser's colour signature (DetectorOptions::min_signature_share): light
// of one wavelength reaches the three colours of the camera's filters in
// fixed shares; line segments whose third colour shows too little of the
// line's share are not the laser (marine snow lit by the floods).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/laser/detector.h"
#include "uwscan/laser/segments.h"

namespace uwscan::laser {

// Drops the segments (of at least min_segment_lines peaks: shorter ones are
// never selected) that show too little of the line's share of light in the
// third colour, before the selection; fills the stats' colour fields. The
// line's share is the median over the peaks bright enough to show it
// clearly. Mono images, or min_signature_share 0: nothing is dropped.
void DropOffColourSegments(const cv::Mat& image, ColourLayout layout, const DetectorOptions& o,
                           const std::vector<Peak>& peaks, std::vector<Segment>* segments,
                           DetectionStats* stats);

}  // namespace uwscan::laser
