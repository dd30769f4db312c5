#include "viewer/inspector.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace caustica::editor {

std::optional<std::string> Inspector::draw(const graph::Plan& plan, const io::ImageData& image, float window_width) {
  std::optional<std::string> chosen;
  ImGui::SetNextWindowPos(ImVec2(std::max(window_width - 430.0f, 390.0f), 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(420, 360), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("inspector", &open, ImGuiWindowFlags_NoBackground | ImGuiWindowFlags_NoBringToFrontOnFocus)) {
    ImGui::End();  // collapsed: no image to place
    return chosen;
  }
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->ChannelsSplit(2);  // 0: the background around the image, 1: the controls over it
  draw->ChannelsSetCurrent(1);
  if (ImGui::BeginCombo("image", inspected.empty() ? "(choose one)" : inspected.c_str())) {
    for (const auto& r : plan.resources) {
      if (r.kind == graph::ResourceKind::image && r.used() && ImGui::Selectable(r.name.c_str(), r.name == inspected)) chosen = r.name;
    }
    ImGui::EndCombo();
  }
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
  ImGui::SliderFloat("exposure (stops)", &exposure_stops, -32.0f, 32.0f);
  ImGui::SameLine();
  if (ImGui::Button("fit")) expose_to_fit(image);
  ImGui::Checkbox("in the main view", &in_main_view);
  if (const int index = plan.find_resource(inspected); index >= 0) {
    const auto& r = plan.resources[static_cast<size_t>(index)];
    ImGui::Text("%u x %u %s", r.width, r.height, graph::format_info(r.format).name);
  }
  const ImVec2 window_min = ImGui::GetWindowPos(),
               window_max(window_min.x + ImGui::GetWindowWidth(), window_min.y + ImGui::GetWindowHeight());
  ImVec2 image_min = ImGui::GetCursorScreenPos(), image_max = image_min;
  const ImVec2 room = ImGui::GetContentRegionAvail();
  if (image.width > 0 && room.x >= 1.0f && room.y >= 1.0f) {
    const float fit = std::min(room.x / static_cast<float>(image.width), room.y / static_cast<float>(image.height));
    const ImVec2 size(std::max(1.0f, std::floor(static_cast<float>(image.width) * fit)),
                      std::max(1.0f, std::floor(static_cast<float>(image.height) * fit)));
    image_min = ImVec2(std::floor(image_min.x), std::floor(image_min.y));
    image_max = ImVec2(image_min.x + size.x, image_min.y + size.y);
    ImGui::Dummy(size);
    panel = {{static_cast<int32_t>(image_min.x), static_cast<int32_t>(image_min.y)},
             {static_cast<uint32_t>(size.x), static_cast<uint32_t>(size.y)}};
  }
  draw->ChannelsSetCurrent(0);
  draw->PushClipRect(window_min, window_max, false);
  const ImU32 background = ImGui::GetColorU32(ImGuiCol_WindowBg);
  draw->AddRectFilled(ImVec2(window_min.x, window_min.y + ImGui::GetFrameHeight()), ImVec2(window_max.x, image_min.y), background);
  draw->AddRectFilled(ImVec2(window_min.x, image_min.y), ImVec2(image_min.x, image_max.y), background);
  draw->AddRectFilled(ImVec2(image_max.x, image_min.y), ImVec2(window_max.x, image_max.y), background);
  draw->AddRectFilled(ImVec2(window_min.x, image_max.y), window_max, background);
  draw->PopClipRect();
  draw->ChannelsMerge();
  ImGui::End();
  return chosen;
}

void Inspector::expose_to_fit(const io::ImageData& image) {
  float brightest = 0.0f;
  for (size_t i = 0; i < image.rgba.size(); ++i) {
    if (i % 4 != 3 && std::isfinite(image.rgba[i])) brightest = std::max(brightest, image.rgba[i]);
  }
  exposure_stops = brightest > 0.0f && !image.display_encoded ? std::clamp(0.0f - std::log2(brightest), -32.0f, 32.0f) : 0.0f;
}

io::ImageData fit_image(const io::ImageData& image, uint32_t width, uint32_t height) {
  io::ImageData out;
  out.width = width;
  out.height = height;
  out.display_encoded = image.display_encoded;
  out.rgba.assign(size_t{width} * height * 4, 0.0f);
  auto span = [](uint32_t i, uint32_t to, uint32_t from) {
    const uint32_t first = static_cast<uint32_t>(uint64_t{i} * from / to);
    return std::pair(first, std::max(first + 1, static_cast<uint32_t>(uint64_t{i + 1} * from / to)));
  };
  for (uint32_t y = 0; y < height; ++y) {
    const auto [y0, y1] = span(y, height, image.height);
    for (uint32_t x = 0; x < width; ++x) {
      const auto [x0, x1] = span(x, width, image.width);
      float* target = &out.rgba[(size_t{y} * width + x) * 4];
      for (uint32_t sy = y0; sy < y1; ++sy) {
        for (uint32_t sx = x0; sx < x1; ++sx) {
          for (int c = 0; c < 4; ++c) target[c] += image.rgba[(size_t{sy} * image.width + sx) * 4 + c];
        }
      }
      for (int c = 0; c < 4; ++c) target[c] /= static_cast<float>((y1 - y0) * (x1 - x0));
    }
  }
  return out;
}

}  // namespace caustica::editor
