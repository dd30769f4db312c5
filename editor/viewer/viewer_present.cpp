#include "viewer/viewer_impl.h"

namespace caustica::editor {

void Viewer::Impl::draw_frame(bool last) {
  const WindowEvents events = window_.take_events();
  fit_frame_budget(handle_input(events));
  // The output goes into the window on the device (a blit) when it is already display-ready
  // 8-bit at the window's size; otherwise, and for screenshots and the inspector, through a
  // read-back to the host.
  const graph::PlannedResource& out = executor_.plan().resources[executor_.plan().outputs.front()];
  const std::string output = out.name;
  const bool main_inspected = inspector_.in_main_view && !inspector_.inspected.empty();
  const bool blit = blit_supported_ && !main_inspected && out.format == graph::Format::rgba8 && out.width == render_size().width &&
                    out.height == render_size().height;
  const bool inspecting = !inspector_.inspected.empty() && (inspector_.open || inspector_.in_main_view);
  const bool read_back =
      !blit || inspecting || screenshot_keys_ > 0 || !pending_screenshot_.empty() || (last && !options_.screenshot.empty());
  const bool must_show = last || inspecting || screenshot_keys_ > 0 || !pending_screenshot_.empty();
  const auto [part, step] =
      budget_.frame_part(now_s(), must_show, executor_.plan().refines_apart, last_result_.converging, last_result_.accumulated);
  const graph::FrameResult frame = executor_.run_frame(read_back, {part, step});
  last_result_ = frame;
  const uint32_t compiled = executor_.compile_count();
  const graph::FrameImage output_image = executor_.frame_image(output);
  const io::ImageData image = read_back ? executor_.read_image(output) : io::ImageData{};
  const io::ImageData inspected = read_back && !inspector_.inspected.empty() ? executor_.read_image(inspector_.inspected) : io::ImageData{};
  if (inspector_.fit_exposure && inspected.width > 0) inspector_.expose_to_fit(inspected);
  inspector_.fit_exposure = false;
  write_screenshots(last, image, inspected);
  if (!budget_.present(now_s(), budget_.showed_result(frame.part) || must_show || last, events.any)) return;
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  if (events.button_moved) ImGui::GetIO().MousePos = ImVec2(static_cast<float>(events.button_x), static_cast<float>(events.button_y));
  ImGui::NewFrame();
  window_.release_held_keys();  // this frame saw them pressed; the next sees them released
  draw_ui(frame, inspected);
  ImGui::Render();
  // An edit in the panels recompiled the graph: the frame's images are gone, show the next one.
  if (blit && executor_.compile_count() != compiled) {
    budget_.not_presented();
    return;
  }
  present(blit ? &output_image : nullptr, main_inspected ? inspected : image, main_inspected, inspected, last);
}

void Viewer::Impl::write_screenshots(bool last, const io::ImageData& image, const io::ImageData& inspected) {
  if (last && !options_.screenshot.empty()) io::write_image(options_.screenshot, inspector_.inspected.empty() ? image : inspected);
  if (!pending_screenshot_.empty()) {
    io::write_image(pending_screenshot_, image);
    std::fprintf(stderr, "view: screenshot %s\n", pending_screenshot_.c_str());
    pending_screenshot_.clear();
  }
  // One file per press, even when several came within one slow frame.
  for (; screenshot_keys_ > 0; --screenshot_keys_) {
    const std::string name = "caustica_view_" + std::to_string(screenshots_++) + ".png";
    io::write_image(name, image);
    session_.report("screenshot " + name, false);
    std::fprintf(stderr, "view: screenshot %s\n", name.c_str());
  }
}

void Viewer::Impl::present(const graph::FrameImage* blitted, const io::ImageData& main, bool main_inspected, const io::ImageData& inspected,
                           bool last) {
  const bool blit = blitted != nullptr;

  uint32_t index = 0;
  VkResult acquired = vkAcquireNextImageKHR(vk_.device(), swapchain_.swapchain.get(), UINT64_MAX, acquired_.get(), VK_NULL_HANDLE, &index);
  if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
    rebuild();
    return;
  }
  if (acquired != VK_SUBOPTIMAL_KHR) vk::check(acquired, "vkAcquireNextImageKHR");
  const float exposure = std::exp2(inspector_.exposure_stops);
  const io::ImageData panel = inspector_.panel.extent.width > 0 && inspected.width > 0
                                  ? fit_image(inspected, inspector_.panel.extent.width, inspector_.panel.extent.height)
                                  : io::ImageData{};
  upload(blit ? io::ImageData{} : main, main_inspected ? exposure : 1.0f, panel, exposure);
  const bool shoot = last && !options_.window_shot.empty();

  vk::check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk::check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
  // The wait on the acquire semaphore is at the transfer stage, so the transition waits for it too.
  passes::image_barrier(cmd_, swapchain_.images[index], VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                        VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_NONE,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkBufferImageCopy regions[2]{};
  if (blit) {
    record_output_blit(cmd_, *blitted, swapchain_.images[index], swapchain_.extent);
  } else {
    regions[0].imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    regions[0].imageExtent = {std::min(uploaded_width_, swapchain_.extent.width), std::min(uploaded_height_, swapchain_.extent.height), 1};
    regions[0].bufferRowLength = uploaded_width_;
    vkCmdCopyBufferToImage(cmd_, staging_.get(), swapchain_.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &regions[0]);
  }
  if (panel.width > 0 && clipped_copy(inspector_.panel.offset, panel.width, panel.height, swapchain_.extent,
                                      VkDeviceSize{uploaded_width_} * uploaded_height_ * 4, regions[1])) {
    // Regions of one copy land in no set order: the panel goes over the main view in a second.
    passes::memory_barrier(cmd_, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                           VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd_, staging_.get(), swapchain_.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &regions[1]);
  }
  VkRenderPassBeginInfo pass{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  pass.renderPass = swapchain_.render_pass.get();
  pass.framebuffer = swapchain_.framebuffers[index].get();
  pass.renderArea.extent = swapchain_.extent;
  vkCmdBeginRenderPass(cmd_, &pass, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd_);
  vkCmdEndRenderPass(cmd_);
  if (shoot) window_shot_.record(vk_, cmd_, swapchain_.images[index], swapchain_.extent);
  vk::check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");

  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSemaphore wait = acquired_.get(), signal = rendered_.get();
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &wait;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd_;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &signal;
  VkFence fence = commands_.fence.get();
  vk::check(vkQueueSubmit(vk_.queue(), 1, &submit, fence), "vkQueueSubmit");
  VkSwapchainKHR sc = swapchain_.swapchain.get();
  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &signal;
  present.swapchainCount = 1;
  present.pSwapchains = &sc;
  present.pImageIndices = &index;
  const VkResult presented = vkQueuePresentKHR(vk_.queue(), &present);
  // One frame in flight: the staging buffer and the semaphores are reused next frame.
  vk::check(vkWaitForFences(vk_.device(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  vk::check(vkResetFences(vk_.device(), 1, &fence), "vkResetFences");
  if (shoot) write_window_shot();
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR || size_changed())
    rebuild();
  else
    vk::check(presented, "vkQueuePresentKHR");
}

bool Viewer::Impl::size_changed() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_.handle, &w, &h);
  return static_cast<uint32_t>(w) != swapchain_.extent.width || static_cast<uint32_t>(h) != swapchain_.extent.height;
}

void Viewer::Impl::rebuild() {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_.handle, &w, &h);
  while ((w == 0 || h == 0) && !glfwWindowShouldClose(window_.handle)) {  // minimised
    glfwWaitEvents();
    glfwGetFramebufferSize(window_.handle, &w, &h);
  }
  build_swapchain(vk_, surface_, window_.handle, swapchain_);
  configure();
}

void Viewer::Impl::upload(const io::ImageData& image, float scale, const io::ImageData& panel, float panel_scale) {
  uploaded_width_ = image.width;
  uploaded_height_ = image.height;
  const VkDeviceSize main_bytes = VkDeviceSize{image.width} * image.height * 4;
  const VkDeviceSize bytes = main_bytes + VkDeviceSize{panel.width} * panel.height * 4;
  if (staging_.size < bytes) {
    staging_ = vk::make_buffer(vk_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "view staging",
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  }
  auto* out = static_cast<uint8_t*>(staging_.mapped);
  encode_bgra(image, scale, out);
  encode_bgra(panel, panel_scale, out + main_bytes);
}

void Viewer::Impl::write_window_shot() {
  io::write_image(options_.window_shot, window_shot_.image(swapchain_.extent));
  // Where the inspector's image lies in the shot, for tests and scripts that cut it out.
  const VkRect2D& panel = inspector_.panel;
  if (panel.extent.width > 0) {
    std::fprintf(stderr, "view: window shot %s; inspector image %s at %d,%d %ux%u\n", options_.window_shot.c_str(),
                 inspector_.inspected.c_str(), panel.offset.x, panel.offset.y, panel.extent.width, panel.extent.height);
  } else {
    std::fprintf(stderr, "view: window shot %s\n", options_.window_shot.c_str());
  }
}

}  // namespace caustica::editor
