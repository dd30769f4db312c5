#pragma once
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace caustica::graph {

enum class Format : uint8_t { rgba8, rgba8_srgb, rgba16f, rgba32f, r16f, rg16f, r32f, rg32f, r32ui, rg32ui, rgba32ui, d32f };

struct FormatInfo {
  Format format;
  const char* name;  // as written in graph files
  VkFormat vk;
  uint32_t bytes_per_texel;
  bool depth;
  const char* glsl_qualifier;  // storage-image layout qualifier; lavapipe cannot read without one
};

const FormatInfo& format_info(Format format);
std::optional<Format> parse_format(std::string_view name);
std::vector<std::string> format_names();

}  // namespace caustica::graph
