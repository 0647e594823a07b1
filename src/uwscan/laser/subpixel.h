// Sub-pixel peak position by a Gaussian fit on raw samples (thesis §5.3).
#pragma once

namespace uwscan::laser {

// Fits a Gaussian to samples[k - h .. k + h] above `background`: a parabola
// in log intensity, least squares weighted by intensity^2 (so that dim,
// noisy tail samples count little). Returns the peak position in sample
// units; falls back to k when the fit is degenerate. Saturated peaks
// (>= saturation) return the midpoint of the flanks at half height.
double GaussianPeakPosition(const float* samples, int count, int k, int half_width,
                            float background, float saturation = 0.999f);

}  // namespace uwscan::laser
