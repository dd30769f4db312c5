#pragma once
// How a material change (dispersion, roughness, a glTF extension) moves an engine's picture against
// the reference's: shared by the refraction and surface tests.
#include <cmath>
#include <cstdint>
#include <vector>

#include "io/image_io.h"

namespace caustica::test {

// Per channel over the pixels where `mask` is set (every pixel without one): the relative L1 of
// the changed picture (`with`) and of the unchanged one (`without`) against the changed reference,
// and the cosine between the picture's change and the reference's.
struct PictureChange {
  double error_with, error_without, cosine;
};
inline PictureChange picture_change(const io::ImageData& with, const io::ImageData& without, const io::ImageData& reference,
                                    const io::ImageData& reference_without, const std::vector<uint8_t>* mask = nullptr) {
  double off_with = 0, off_without = 0, total = 0, dot = 0, change_norm = 0, reference_change_norm = 0;
  for (size_t i = 0; i < reference.rgba.size() / 4; ++i) {
    if (mask && !(*mask)[i]) continue;
    for (size_t k = i * 4; k < i * 4 + 3; ++k) {
      const double truth = static_cast<double>(reference.rgba[k]), change = double(with.rgba[k]) - double(without.rgba[k]),
                   reference_change = truth - double(reference_without.rgba[k]);
      off_with += std::abs(double(with.rgba[k]) - truth);
      off_without += std::abs(double(without.rgba[k]) - truth);
      total += std::abs(truth);
      dot += change * reference_change;
      change_norm += change * change;
      reference_change_norm += reference_change * reference_change;
    }
  }
  return {off_with / total, off_without / total, dot / std::sqrt(change_norm * reference_change_norm)};
}

}  // namespace caustica::test
