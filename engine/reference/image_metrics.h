#pragma once
// How far an engine image is from a reference image (docs/accuracy.md): the caustic metrics on a
// matched blur, and the per-value differences of the images as they are.
#include <cstdint>

#include "io/image_io.h"

namespace caustica::reference {

struct ImageComparison {
  // Both images blurred by the same Gaussian (sigma in pixels; 0: none), on luminance:
  // sum |A - B| / sum |B|. The blur stands for the footprint over which a viewer averages a
  // caustic, so that photon noise at a scale below it is not counted as error.
  double relative_l1 = 0;
  double energy_ratio = 0;  // sum A / sum B, on luminance: above 1, A created energy
  // The same L1 with each image divided by its own sum (0 to 2): where the energy goes, whatever
  // its total, so that a method losing flux evenly is told apart from one putting it elsewhere.
  double shape_l1 = 0;
  // On the unblurred colour values: mean and root-mean-square of |A - B|, the largest |A - B|, and
  // the peak signal-to-noise ratio 20 log10(1 / rms) in dB, taking 1 as the peak.
  double mean_error = 0, rms_error = 0, psnr = 0, max_error = 0;
  uint64_t nonfinite_a = 0, nonfinite_b = 0;  // NaN or Inf values (counted as 0 in the sums)
};

// Throws InputError when the sizes differ.
ImageComparison compare_images(const io::ImageData& a, const io::ImageData& b, double blur_sigma);

// A separable Gaussian blur of luminance, truncated at 3 sigma, clamped at the borders.
std::vector<double> blurred_luminance(const io::ImageData& image, double sigma, uint64_t* nonfinite = nullptr);

}  // namespace caustica::reference
