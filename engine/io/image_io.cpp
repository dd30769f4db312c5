#include "io/image_io.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "io/files.h"

namespace caustica::io {
namespace {

constexpr int kMaxImageSide = 65536;

void check_size(const std::string& path, long width, long height) {
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide) {
    throw InputError(path + ": image size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range");
  }
}

// An EXR's channels in ImageData's order, each a float at a stride of four.
constexpr const char* kChannels[] = {"R", "G", "B", "A"};
constexpr size_t kPixelBytes = 4 * sizeof(float);

ImageData sized(long width, long height) {
  ImageData image;
  image.width = static_cast<uint32_t>(width);
  image.height = static_cast<uint32_t>(height);
  image.rgba.assign(size_t{image.width} * image.height * 4, 1.0f);
  return image;
}

// RGBA in 32-bit float, ZIP-compressed: the values as they are.
void write_exr(const std::string& path, const ImageData& image) {
  Imf::Header header(static_cast<int>(image.width), static_cast<int>(image.height));
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  for (size_t c = 0; c < 4; ++c) {
    header.channels().insert(kChannels[c], Imf::Channel(Imf::FLOAT));
    // OpenEXR's slices take a writable pointer for reading and writing alike; nothing is written here.
    char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgba.data() + c));
    frame.insert(kChannels[c], Imf::Slice(Imf::FLOAT, base, kPixelBytes, kPixelBytes * image.width));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(static_cast<int>(image.height));
}

// Any channel layout: RGB(A) as it is, luminance (Y) to grey; a missing alpha reads as 1.
ImageData read_exr(const std::string& path) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i window = file.header().dataWindow();
  const long width = long{window.max.x} - window.min.x + 1, height = long{window.max.y} - window.min.y + 1;
  check_size(path, width, height);
  ImageData image = sized(width, height);
  const Imf::ChannelList& channels = file.header().channels();
  const bool grey = channels.findChannel("R") == nullptr && channels.findChannel("Y") != nullptr;
  if (channels.findChannel("R") == nullptr && !grey) {
    // Read on, it would be a black image: a photon shard's sums are in channels of their own.
    throw InputError(path + ": cannot read image: it has no R or Y channel" +
                     (channels.findChannel("units_low.R") ? " (a photon shard: caustica merge makes the map)" : ""));
  }
  // A camera shard is some rows of an image: read as the image, it would be a strip of it.
  if (const auto* kind = file.header().findTypedAttribute<Imf::StringAttribute>("caustica.kind");
      kind && kind->value() == "caustica camera shard") {
    throw InputError(path + ": cannot read image: it is a camera shard, some rows of an image (caustica merge makes the image)");
  }
  Imf::FrameBuffer frame;
  for (size_t c = 0; c < (grey ? 1 : 4); ++c) {
    frame.insert(grey ? "Y" : kChannels[c], Imf::Slice::Make(Imf::FLOAT, image.rgba.data() + c, window, kPixelBytes,
                                                             kPixelBytes * image.width, 1, 1, c == 3 ? 1.0 : 0.0));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  if (grey) {
    for (size_t p = 0; p < image.rgba.size(); p += 4) image.rgba[p + 1] = image.rgba[p + 2] = image.rgba[p];
  }
  return image;
}

struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

// PNG, JPEG, Radiance HDR, BMP, TGA, PSD, GIF, PIC and PNM through stb_image: 8 and 16-bit files
// scaled to 0-1 as stored (display-encoded), HDR files as the linear values they hold.
ImageData read_stb(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  if (!stbi_info(path.c_str(), &width, &height, &channels)) {
    throw InputError(path + ": cannot read image: " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown format") +
                     " (EXR, PNG, JPEG, HDR, BMP, TGA, PSD, GIF, PIC and PNM are read)");
  }
  check_size(path, width, height);
  ImageData image = sized(width, height);
  const size_t count = size_t{image.width} * image.height * 4;
  auto failed = [&] {
    return InputError(path + ": cannot read image: " + (stbi_failure_reason() ? stbi_failure_reason() : "corrupt file"));
  };
  if (stbi_is_hdr(path.c_str())) {
    std::unique_ptr<float, StbFree> pixels(stbi_loadf(path.c_str(), &width, &height, &channels, 4));
    if (!pixels) throw failed();
    std::copy_n(pixels.get(), count, image.rgba.begin());
  } else if (stbi_is_16_bit(path.c_str())) {
    std::unique_ptr<uint16_t, StbFree> pixels(stbi_load_16(path.c_str(), &width, &height, &channels, 4));
    if (!pixels) throw failed();
    for (size_t i = 0; i < count; ++i) image.rgba[i] = static_cast<float>(pixels.get()[i]) / 65535.0f;
    image.display_encoded = true;
  } else {
    std::unique_ptr<uint8_t, StbFree> pixels(stbi_load(path.c_str(), &width, &height, &channels, 4));
    if (!pixels) throw failed();
    for (size_t i = 0; i < count; ++i) image.rgba[i] = static_cast<float>(pixels.get()[i]) / 255.0f;
    image.display_encoded = true;
  }
  return image;
}

}  // namespace

float srgb_encode(float linear) {
  linear = std::clamp(linear, 0.0f, 1.0f);
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float half_to_float(uint16_t half) {
  const uint32_t sign = static_cast<uint32_t>(half >> 15) << 31;
  const uint32_t exponent = (half >> 10) & 0x1F;
  const uint32_t mantissa = half & 0x3FF;
  float magnitude;
  if (exponent == 0)
    magnitude = std::ldexp(static_cast<float>(mantissa), -24);
  else if (exponent == 31)
    magnitude = mantissa ? NAN : INFINITY;
  else
    magnitude = std::ldexp(static_cast<float>(mantissa | 0x400), static_cast<int>(exponent) - 25);
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
  std::string failure;
  if (ext == ".png") {
    std::vector<uint8_t> bytes(image.rgba.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
      float v = image.rgba[i];
      if (!image.display_encoded && i % 4 != 3) v = srgb_encode(v);
      bytes[i] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
    errno = 0;
    if (!stbi_write_png(temp.c_str(), static_cast<int>(image.width), static_cast<int>(image.height), 4, bytes.data(),
                        static_cast<int>(image.width * 4))) {
      failure = errno ? std::strerror(errno) : "the PNG writer failed";
    }
  } else {
    try {
      write_exr(temp.string(), image);
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw InputError(path + ": cannot write: " + failure);
  }
  commit(temp, target);
}

ImageData read_image(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": cannot read image: " + (std::filesystem::exists(path, ec) ? "not a file" : "no such file"));
  }
  if (!Imf::isOpenExrFile(path.c_str())) return read_stb(path);
  try {
    return read_exr(path);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read image: " + e.what());
  }
}

}  // namespace caustica::io
