#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "io/files.h"

namespace caustica::io {

struct ImageData {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> rgba;         // width * height * 4, top row first
  bool display_encoded = false;    // values are already sRGB-encoded (8-bit outputs of a tonemap)
};

// Writes PNG (8-bit sRGB) or EXR (32-bit float, the values as they are) by extension. The file is
// written under a temporary name and renamed, so a failure leaves no half-written file.
void write_image(const std::string& path, const ImageData& image);
ImageData read_image(const std::string& path);

// Throws before any work is done when an image output cannot be written: its folder is missing
// or it does not end in .png or .exr. Returns the lower-case extension.
std::string check_image_output(const std::string& path);

float srgb_encode(float linear);
float half_to_float(uint16_t half);

}  // namespace caustica::io
