#include "viewer/viewer_impl.h"

namespace caustica::editor {

void Viewer::Impl::init_imgui() {
  VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pool_info.maxSets = 16;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = sizes;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  vk::check(vkCreateDescriptorPool(vk_.device(), &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
  imgui_pool_ = vk::OwnedDescriptorPool(vk_, pool);
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's folder
  ImGui_ImplGlfw_InitForVulkan(window_.handle, true);
  window_.hold_short_key_taps();
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = vk_.instance();
  info.PhysicalDevice = vk_.physical_device();
  info.Device = vk_.device();
  info.QueueFamily = vk_.queue_family();
  info.Queue = vk_.queue();
  info.DescriptorPool = pool;
  info.MinImageCount = 2;
  info.ImageCount = static_cast<uint32_t>(swapchain_.images.size());
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = [](VkResult r) { vk::check(r, "ImGui Vulkan backend"); };
  ImGui_ImplVulkan_Init(&info, swapchain_.render_pass.get());
  vk_.submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
  imgui_ready_ = true;

  commands_ = vk::make_frame_commands(vk_);
  cmd_ = commands_.cmd;
  acquired_ = vk::make_semaphore(vk_);
  rendered_ = vk::make_semaphore(vk_);
}

bool Viewer::Impl::handle_input(const WindowEvents& events) {
  ImGuiIO& io = ImGui::GetIO();
  // What input can move: the camera and the lights, as the executor's scene has them now (a
  // reloaded scene file starts from its own).
  struct {
    scene::View camera;
    std::vector<scene::Light> lights;
  } moved{executor_.scene()->camera(), executor_.scene()->lights()};
  bool changed = false;
  const bool scripted = frames_drawn_ >= options_.move_first && frames_drawn_ < options_.move_end;
  if (scripted && options_.orbit_degrees != 0.0f) {
    moved.camera.orbit(options_.orbit_degrees);
    changed = true;
  }
  // The light the arrows move (a reloaded scene may have fewer).
  scene::Light* chosen = moved_light_ < moved.lights.size() ? &moved.lights[moved_light_] : nullptr;
  if (scripted && options_.move_light != 0.0f && chosen) {
    chosen->view.position.x += options_.move_light;
    changed = true;
  }
  // A drag moves the view only on frames where the mouse moved: a held button between a hand's
  // events is no input for the frame budget (editor/model/view_budget.h).
  const bool dragged = ImGui::IsMouseDragging(ImGuiMouseButton_Left) && (io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f);
  if (!io.WantCaptureMouse && (dragged || io.MouseWheel != 0.0f)) {
    // Orbit: yaw and pitch of the camera's offset from its target, distance by the wheel.
    glm::vec3 offset = moved.camera.position - moved.camera.target;
    const float distance = glm::length(offset) * std::pow(0.9f, io.MouseWheel);
    float yaw = std::atan2(offset.x, offset.z) - io.MouseDelta.x * 0.01f;
    float pitch = std::clamp(std::asin(offset.y / glm::length(offset)) + io.MouseDelta.y * 0.01f, -1.5f, 1.5f);
    moved.camera.position =
        moved.camera.target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    changed = true;
  }
  for (const auto& key : events.pressed) {
    if (owner_.on_key && owner_.on_key(key)) continue;
    if (key.key == GLFW_KEY_ESCAPE) quit_ = true;
    if (key.key == GLFW_KEY_F1) show_help_ = !show_help_;
    if (io.WantCaptureKeyboard) continue;  // typing into a field
    constexpr float kStep = 0.05f;
    glm::vec3 light_step(0.0f);
    switch (key.key) {
      case GLFW_KEY_TAB: panels_hidden_ = !panels_hidden_; break;
      case GLFW_KEY_C: continuous_ = !continuous_; break;
      case GLFW_KEY_P: ++screenshot_keys_; break;
      case GLFW_KEY_R:
        moved.camera = home_camera_;
        for (size_t i = 0; i < std::min(moved.lights.size(), home_lights_.size()); ++i) moved.lights[i].view.position = home_lights_[i];
        changed = true;
        break;
      case GLFW_KEY_L:
        if (!moved.lights.empty()) {
          moved_light_ = (moved_light_ + 1) % static_cast<uint32_t>(moved.lights.size());
          chosen = &moved.lights[moved_light_];
          std::printf("view: the arrows move light %u (%s)\n", moved_light_, scene::light_type_name(chosen->type));
          std::fflush(stdout);
        }
        break;
      case GLFW_KEY_LEFT: light_step.x = -kStep; break;
      case GLFW_KEY_RIGHT: light_step.x = kStep; break;
      case GLFW_KEY_UP: light_step.z = -kStep; break;
      case GLFW_KEY_DOWN: light_step.z = kStep; break;
      case GLFW_KEY_PAGE_UP: light_step.y = kStep; break;
      case GLFW_KEY_PAGE_DOWN: light_step.y = -kStep; break;
      default: break;
    }
    if (light_step != glm::vec3(0.0f) && chosen) {
      chosen->view.position += light_step;
      changed = true;
    }
  }
  if (changed) {
    executor_.set_view(moved.camera, std::move(moved.lights));
  }
  return changed;
}

void Viewer::Impl::draw_ui(const graph::FrameResult& frame, const io::ImageData& inspected) {
  inspector_.panel = {};
  if (panels_hidden_) return;
  // Fits 1280x720 beside the picture: the graph's panel on the left, the inspector on the right.
  const float height = std::min(700.0f, static_cast<float>(swapchain_.extent.height) - 20.0f);
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(370, height), ImGuiCond_FirstUseEver);
  // The label shows the graph and the scene; the id after ### keeps the panel's place when they change.
  ImGui::Begin((shown_name() + "###caustica").c_str());
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextColored(session_.status_is_error ? ImVec4(1, 0.4f, 0.3f, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1), "%s", session_.status.c_str());
  ImGui::PopTextWrapPos();
  ImGui::Text("frame: GPU %.2f ms, CPU %.2f ms, %.0f ms in all", frame.gpu_ms, frame.cpu_ms, budget_.last_wall_ms());
  const ViewBudget::Setting& setting = budget_.setting();
  const StillLevels& still_levels = budget_.still_levels();
  if (setting.step.divider > 1) {
    ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "moving: 1/%u of the window's size each way%s (budget %.0f ms)", setting.step.divider,
                       setting.step.lowered ? ", the graph's while_moving values" : "", options_.budget_ms);
  }
  if (setting.still_values && still_levels.level() == 0)
    ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "still: the graph's while_still values");
  if (setting.still_values && still_levels.level() > 0) {
    ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1),
                       "still: the graph's while_still values, level %zu of %zu (moved on refining frames of %.0f ms)",
                       still_levels.level() + 1, still_levels.levels(), still_levels.judged());
  }
  if (frame.accumulated > 0) {
    ImGui::Text("mean of %llu frames%s", static_cast<unsigned long long>(frame.accumulated), frame.converging ? "" : ", converged");
  }
  if (frame.part != graph::FramePart::whole) {
    ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "still: refining (%llu frames), the picture shown every %.1f to %.1f s%s",
                       static_cast<unsigned long long>(frame.frame.since_reset + 1), editor::kShowAfter, editor::kShowAtMost,
                       budget_.display_frames() > 1 ? (" in " + std::to_string(budget_.display_frames()) + " frames").c_str() : "");
  }
  ImGui::TextDisabled("F1 help, Tab hide panels");
  ImGui::Checkbox("continuous (C): render every frame, for timing", &continuous_);
  frame_panel(frame, executor_.plan(), gpu_history_);
  auto reconfigure = [this] { configure(); };
  if (ImGui::CollapsingHeader("enable passes")) pass_switches(session_, reconfigure);
  counters_and_memory(frame, executor_.plan(), executor_.scene());
  if (options_.parameter_panel && ImGui::CollapsingHeader("parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
    parameter_panel(session_, reconfigure);
    ImGui::InputText("##save_as", save_as_, sizeof save_as_);
    ImGui::SameLine();
    if (ImGui::Button(save_as_[0] ? "save as" : "save")) save(save_as_[0] ? std::string(save_as_) : session_.graph_file);
  }
  ImGui::Checkbox("resource inspector", &inspector_.open);
  ImGui::End();
  if (inspector_.open) {
    if (auto chosen = inspector_.draw(executor_.plan(), inspected, static_cast<float>(swapchain_.extent.width))) select_inspected(*chosen);
  }
  if (owner_.extra_ui) owner_.extra_ui(frame);
  if (show_help_) {
    ImGui::SetNextWindowPos(ImVec2(390, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("help", &show_help_);
    ImGui::TextUnformatted(kViewerKeys);
    ImGui::End();
  }
}

void Viewer::Impl::save(const std::string& path) {
  try {
    io::write_text_atomically(path, graph::graph_text_with_values(edited(session_)));
    session_.status = "saved " + path;
    session_.status_is_error = false;
    if (path == session_.graph_file) session_.edits.clear();  // the file's defaults hold them now
  } catch (const std::exception& e) {
    session_.status = e.what();
    session_.status_is_error = true;
  }
}

void Viewer::Impl::select_inspected(const std::string& name) {
  inspector_.inspected = name;
  configure();
  inspector_.fit_exposure = true;
}

}  // namespace caustica::editor
