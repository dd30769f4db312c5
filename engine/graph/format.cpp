#include "graph/format.h"

#include <array>

namespace caustica::graph {
namespace {
constexpr std::array<FormatInfo, 12> kFormats{{
    {Format::rgba8, "rgba8", VK_FORMAT_R8G8B8A8_UNORM, 4, false, "rgba8"},
    {Format::rgba8_srgb, "rgba8_srgb", VK_FORMAT_R8G8B8A8_SRGB, 4, false, ""},
    {Format::rgba16f, "rgba16f", VK_FORMAT_R16G16B16A16_SFLOAT, 8, false, "rgba16f"},
    {Format::rgba32f, "rgba32f", VK_FORMAT_R32G32B32A32_SFLOAT, 16, false, "rgba32f"},
    {Format::r16f, "r16f", VK_FORMAT_R16_SFLOAT, 2, false, "r16f"},
    {Format::rg16f, "rg16f", VK_FORMAT_R16G16_SFLOAT, 4, false, "rg16f"},
    {Format::r32f, "r32f", VK_FORMAT_R32_SFLOAT, 4, false, "r32f"},
    {Format::rg32f, "rg32f", VK_FORMAT_R32G32_SFLOAT, 8, false, "rg32f"},
    {Format::r32ui, "r32ui", VK_FORMAT_R32_UINT, 4, false, "r32ui"},
    {Format::rg32ui, "rg32ui", VK_FORMAT_R32G32_UINT, 8, false, "rg32ui"},
    {Format::rgba32ui, "rgba32ui", VK_FORMAT_R32G32B32A32_UINT, 16, false, "rgba32ui"},
    {Format::d32f, "d32f", VK_FORMAT_D32_SFLOAT, 4, true, ""},
}};
}  // namespace

const FormatInfo& format_info(Format format) {
  return kFormats[static_cast<size_t>(format)];
}

std::optional<Format> parse_format(std::string_view name) {
  for (const auto& info : kFormats) {
    if (name == info.name) return info.format;
  }
  return std::nullopt;
}

std::vector<std::string> format_names() {
  std::vector<std::string> names;
  for (const auto& info : kFormats) names.emplace_back(info.name);
  return names;
}

}  // namespace caustica::graph
