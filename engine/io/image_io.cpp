#include "io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "io/files.h"

namespace caustica::io {

float srgb_encode(float linear) {
  linear = std::clamp(linear, 0.0f, 1.0f);
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float half_to_float(uint16_t half) {
  const uint32_t sign = static_cast<uint32_t>(half >> 15) << 31;
  const uint32_t exponent = (half >> 10) & 0x1F;
  const uint32_t mantissa = half & 0x3FF;
  float magnitude;
  if (exponent == 0) magnitude = std::ldexp(static_cast<float>(mantissa), -24);
  else if (exponent == 31) magnitude = mantissa ? NAN : INFINITY;
  else magnitude = std::ldexp(static_cast<float>(mantissa | 0x400), static_cast<int>(exponent) - 25);
  uint32_t bits;
  std::memcpy(&bits, &magnitude, 4);
  bits |= sign;
  std::memcpy(&magnitude, &bits, 4);
  return magnitude;
}

std::string check_image_output(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".png" && ext != ".exr") throw UsageError(path + ": output must end in .png or .exr");
  check_output_file(path);
  return ext;
}

void write_image(const std::string& path, const ImageData& image) {
  std::filesystem::path target(path);
  const std::string ext = check_image_output(path);
  std::filesystem::path temp = temporary_name(target);
  auto out = OIIO::ImageOutput::create(temp.string());
  if (!out) throw InputError(path + ": cannot create an image writer: " + OIIO::geterror());
  bool ok;
  if (ext == ".png") {
    std::vector<uint8_t> bytes(image.rgba.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
      float v = image.rgba[i];
      if (!image.display_encoded && i % 4 != 3) v = srgb_encode(v);
      bytes[i] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 4, OIIO::TypeDesc::UINT8);
    ok = out->open(temp.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  } else {
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height), 4, OIIO::TypeDesc::FLOAT);
    ok = out->open(temp.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data());
  }
  ok = out->close() && ok;
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw InputError(path + ": cannot write: " + out->geterror());
  }
  commit(temp, target);
}

ImageData read_image(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw InputError(path + ": cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.width > 65536 || spec.height > 65536) {
    throw InputError(path + ": image size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " is out of range");
  }
  ImageData image;
  image.width = static_cast<uint32_t>(spec.width);
  image.height = static_cast<uint32_t>(spec.height);
  const int channels = spec.nchannels;
  std::vector<float> pixels(static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) * static_cast<size_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data())) {
    throw InputError(path + ": cannot read image: " + in->geterror());
  }
  image.display_encoded = spec.format == OIIO::TypeDesc::UINT8;
  image.rgba.assign(static_cast<size_t>(image.width) * image.height * 4, 1.0f);
  for (size_t p = 0; p < static_cast<size_t>(image.width) * image.height; ++p) {
    for (int c = 0; c < std::min(channels, 4); ++c) image.rgba[p * 4 + static_cast<size_t>(c)] = pixels[p * static_cast<size_t>(channels) + static_cast<size_t>(c)];
    if (channels == 1) image.rgba[p * 4 + 1] = image.rgba[p * 4 + 2] = image.rgba[p * 4];
  }
  return image;
}

}  // namespace caustica::io
