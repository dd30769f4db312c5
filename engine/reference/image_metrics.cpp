#include "reference/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace caustica::reference {
std::vector<double> blurred_luminance(const io::ImageData& image, double sigma, uint64_t* nonfinite) {
  const size_t w = image.width, h = image.height;
  std::vector<double> lum(w * h);
  for (size_t p = 0; p < w * h; ++p) {
    const float* px = &image.rgba[p * 4];
    const double l = 0.2126 * double(px[0]) + 0.7152 * double(px[1]) + 0.0722 * double(px[2]);
    const bool finite = std::isfinite(l);
    if (!finite && nonfinite) ++*nonfinite;
    lum[p] = finite ? l : 0.0;
  }
  if (sigma <= 0) return lum;
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> kernel(static_cast<size_t>(2 * radius + 1));
  double total = 0;
  for (int i = -radius; i <= radius; ++i) total += kernel[static_cast<size_t>(i + radius)] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& k : kernel) k /= total;
  std::vector<double> tmp(w * h);
  auto pass = [&](const std::vector<double>& from, std::vector<double>& to, bool vertical) {
    for (size_t y = 0; y < h; ++y) {
      for (size_t x = 0; x < w; ++x) {
        double sum = 0;
        for (int i = -radius; i <= radius; ++i) {
          const long sx = vertical ? long(x) : std::clamp(long(x) + i, 0L, long(w) - 1);
          const long sy = vertical ? std::clamp(long(y) + i, 0L, long(h) - 1) : long(y);
          sum += kernel[static_cast<size_t>(i + radius)] * from[size_t(sy) * w + size_t(sx)];
        }
        to[y * w + x] = sum;
      }
    }
  };
  pass(lum, tmp, false);
  pass(tmp, lum, true);
  return lum;
}

ImageComparison compare_images(const io::ImageData& a, const io::ImageData& b, double blur_sigma) {
  if (a.width != b.width || a.height != b.height) {
    throw InputError("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " and " +
                     std::to_string(b.width) + "x" + std::to_string(b.height));
  }
  ImageComparison result;
  const auto la = blurred_luminance(a, blur_sigma, &result.nonfinite_a);
  const auto lb = blurred_luminance(b, blur_sigma, &result.nonfinite_b);
  double difference = 0, sum_a = 0, sum_b = 0;
  for (size_t i = 0; i < la.size(); ++i) {
    difference += std::abs(la[i] - lb[i]);
    sum_a += la[i];
    sum_b += lb[i];
  }
  if (sum_a != 0 && sum_b != 0) {
    for (size_t i = 0; i < la.size(); ++i) result.shape_l1 += std::abs(la[i] / sum_a - lb[i] / sum_b);
  }
  result.relative_l1 = sum_b != 0 ? difference / std::abs(sum_b) : (difference == 0 ? 0.0 : std::numeric_limits<double>::infinity());
  result.energy_ratio = sum_b != 0 ? sum_a / sum_b : (sum_a == 0 ? 1.0 : std::numeric_limits<double>::infinity());
  // Per colour value, unblurred; a NaN or Inf counts as 0, as in the sums above.
  double absolute = 0, squared = 0, peak = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double va = std::isfinite(a.rgba[i]) ? static_cast<double>(a.rgba[i]) : 0.0,
                 vb = std::isfinite(b.rgba[i]) ? static_cast<double>(b.rgba[i]) : 0.0;
    const double d = std::abs(va - vb);
    absolute += d;
    squared += d * d;
    result.max_error = std::max(result.max_error, d);
    peak = std::max(peak, vb);
  }
  const double values = 3.0 * a.width * a.height;
  result.mean_error = absolute / values;
  result.rms_error = std::sqrt(squared / values);
  // The peak is the reference's brightest value, not 1: a caustic map's flux per texel is far below 1,
  // and against 1 any map of it would score a PSNR of 90 dB or more. A display image with white in
  // it has the usual peak of 1.
  if (result.rms_error == 0)
    result.psnr = std::numeric_limits<double>::infinity();
  else
    result.psnr = peak > 0 ? 20.0 * std::log10(peak / result.rms_error) : -std::numeric_limits<double>::infinity();
  return result;
}

}  // namespace caustica::reference
