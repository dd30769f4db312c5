// Tests on the real device (lavapipe in CI) with validation and synchronization validation on:
// any validation message fails the test.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>

#include <filesystem>
#include <fstream>

#include "builtin_passes.h"
#include "core/error.h"
#include "core/paths.h"
#include "graph/executor.h"
#include "graph/report.h"
#include "shader/shader_interface.h"
#include "vk/pipeline.h"

using namespace caustica;

namespace {

struct Engine {
  vk::Context vk{{"", true, false}};
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
  graph::Executor executor{vk, shaders, passes::builtin_registry()};
};

graph::GraphDesc core_demo(const std::vector<std::string>& sets = {}) {
  auto g = graph::load_graph_file((data_dir() / "graphs/core_demo.json").string());
  graph::apply_overrides(g, sets);
  return g;
}

float to_half_precision(float v) {
  // rgba16f keeps 11 significant bits: model the storage rounding of the intermediate images.
  if (v == 0.0f) return 0.0f;
  int exponent;
  float mantissa = std::frexp(v, &exponent);
  return std::ldexp(std::round(mantissa * 2048.0f) / 2048.0f, exponent);
}

// The CPU model of shaders/core/pattern.frag with the pass's default parameters.
std::vector<float> model_pattern(int w, int h, float sun_intensity) {
  const float tau = 6.28318530718f, frequency = 4.0f, sun_x = 0.7f, sun_y = 0.3f, radius = 0.08f;
  std::vector<float> out(static_cast<size_t>(w * h * 4));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(w), v = (static_cast<float>(y) + 0.5f) / static_cast<float>(h);
      float dx = u - sun_x, dy = v - sun_y;
      float sun = sun_intensity * std::exp(-(dx * dx + dy * dy) / (radius * radius));
      float* p = &out[static_cast<size_t>((y * w + x) * 4)];
      p[0] = to_half_precision(0.5f * (0.5f + 0.5f * std::sin(tau * frequency * u)) + sun);
      p[1] = to_half_precision(0.5f * v + sun);
      p[2] = to_half_precision(0.5f * (0.5f + 0.5f * std::cos(tau * frequency * v)) + sun);
      p[3] = 1.0f;
    }
  }
  return out;
}

std::vector<float> model_blur(const std::vector<float>& in, int w, int h, int radius, bool vertical) {
  std::vector<float> out(in.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 4; ++c) {
        float sum = 0;
        for (int k = -radius; k <= radius; ++k) {
          int sx = vertical ? x : std::clamp(x + k, 0, w - 1);
          int sy = vertical ? std::clamp(y + k, 0, h - 1) : y;
          sum += in[static_cast<size_t>((sy * w + sx) * 4 + c)];
        }
        out[static_cast<size_t>((y * w + x) * 4 + c)] = to_half_precision(sum / static_cast<float>(2 * radius + 1));
      }
    }
  }
  return out;
}

float srgb(float l) {
  l = std::clamp(l, 0.0f, 1.0f);
  return l <= 0.0031308f ? 12.92f * l : 1.055f * std::pow(l, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

TEST(Device, CoreDemoMatchesItsCpuModel) {
  Engine e;
  const int w = 96, h = 64, radius = 2;
  const float exposure = 0.8f;
  e.executor.configure(core_demo({"blur_radius=2", "exposure=0.8"}), w, h, {.retained = {"hdr"}});
  auto frame = e.executor.run_frame(true);
  auto ldr = e.executor.read_image("ldr");
  auto hdr = e.executor.read_image("hdr");
  ASSERT_EQ(ldr.width, static_cast<uint32_t>(w));
  ASSERT_EQ(ldr.height, static_cast<uint32_t>(h));

  auto pattern = model_pattern(w, h, 6.0f);
  double worst_hdr = 0;
  for (size_t i = 0; i < pattern.size(); ++i)
    worst_hdr = std::max(worst_hdr, std::abs(double(hdr.rgba[i]) - double(pattern[i])) / double(std::max(1.0f, pattern[i])));
  EXPECT_LT(worst_hdr, 2e-3) << "the full-screen pass differs from its model";

  auto blurred = model_blur(model_blur(pattern, w, h, radius, false), w, h, radius, true);
  double worst = 0;
  uint64_t bright = 0, borderline = 0;
  for (int p = 0; p < w * h; ++p) {
    float r = blurred[static_cast<size_t>(p * 4)] * exposure, g = blurred[static_cast<size_t>(p * 4 + 1)] * exposure,
          b = blurred[static_cast<size_t>(p * 4 + 2)] * exposure;
    float lum = 0.2126f * r + 0.7152f * g + 0.0722f * b;
    bright += lum > 1.0f;
    borderline += std::abs(lum - 1.0f) < 2e-3f;
    float expected[3] = {srgb(1 - std::exp(-r)), srgb(1 - std::exp(-g)), srgb(1 - std::exp(-b))};
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(ldr.rgba[static_cast<size_t>(p * 4 + c)]) - double(expected[c])));
  }
  EXPECT_LE(worst, 1.5 / 255.0) << "8-bit output differs from the CPU model by " << worst * 255 << " levels";
  // No banding: the 8-bit output is dithered, so over 8 x 8 pixels its mean follows the exact
  // value, where plain rounding leaves each block off by its own rounding error (0.12 of a level
  // on average on this image when written, 0.03 with the dither).
  double block_error = 0;
  int blocks = 0;
  for (int by = 0; by + 8 <= h; by += 8) {
    for (int bx = 0; bx + 8 <= w; bx += 8) {
      for (int c = 0; c < 3; ++c) {
        double difference = 0;
        for (int y = by; y < by + 8; ++y) {
          for (int x = bx; x < bx + 8; ++x) {
            const size_t i = static_cast<size_t>((y * w + x) * 4);
            const float v = 1 - std::exp(-blurred[i + static_cast<size_t>(c)] * exposure);
            difference += double(ldr.rgba[i + static_cast<size_t>(c)]) - double(srgb(v));
          }
        }
        block_error += std::abs(difference / 64.0) * 255.0;
        ++blocks;
      }
    }
  }
  std::printf("mean 8x8-block error of the 8-bit output: %.3f levels\n", block_error / blocks);
  EXPECT_LT(block_error / blocks, 0.07);
  ASSERT_TRUE(frame.counters.count("tonemap.bright_pixels"));
  EXPECT_GT(bright, 100u);  // the sun is brighter than white: the counter must see it
  EXPECT_LE(std::llabs(std::llround(frame.counters["tonemap.bright_pixels"]) - static_cast<long long>(bright)),
            static_cast<long long>(borderline));
  EXPECT_EQ(e.vk.validation_messages(), 0u);
}

TEST(Device, PerPassTimestampsSumToTheFrame) {
  Engine e;
  // Each timestamp costs lavapipe tens of microseconds; at 640x360 the passes are long enough
  // that the gaps between them stay well under the 10% the trace promises. On a loaded machine
  // the driver's threads can be preempted between passes, which widens one frame's gaps, so the
  // closest of several frames is held to the 10%; a wrong timestamp scheme misses on every frame.
  // A GPU runs this frame in about 70 us, of which its barriers take a few each: 20 us more.
  e.executor.configure(core_demo(), 640, 360);
  e.executor.run_frame(false);  // pipelines JIT-compile on first use
  bool within = false;
  for (int f = 0; f < 12 && !within; ++f) {
    auto frame = e.executor.run_frame(false);
    double sum = 0;
    for (const auto& p : frame.passes) {
      EXPECT_GT(p.gpu_ms, 0.0) << p.name;
      sum += p.gpu_ms;
    }
    ASSERT_GT(frame.gpu_ms, 0.0);
    EXPECT_LE(sum, frame.gpu_ms * 1.0001) << "passes cannot take longer than the frame that holds them";
    within = frame.gpu_ms - sum < 0.10 * frame.gpu_ms + 0.020;
  }
  EXPECT_TRUE(within) << "per-pass GPU times never came within 10% (and 20 us) of the frame";
  EXPECT_EQ(e.vk.validation_messages(), 0u);
}

TEST(Device, RecompilesOnlyWhenGraphOrSizeChanges) {
  Engine e;
  auto g = core_demo();
  EXPECT_TRUE(e.executor.configure(g, 64, 64));
  e.executor.run_frame(false);
  EXPECT_FALSE(e.executor.configure(g, 64, 64));
  EXPECT_FALSE(e.executor.configure(core_demo(), 64, 64));  // same file, loaded again
  EXPECT_EQ(e.executor.compile_count(), 1u);
  EXPECT_TRUE(e.executor.configure(g, 80, 64));
  e.executor.run_frame(false);
  EXPECT_TRUE(e.executor.configure(core_demo({"blur_radius=5"}), 80, 64));
  e.executor.run_frame(true);
  EXPECT_EQ(e.executor.compile_count(), 3u);
  EXPECT_EQ(e.vk.validation_messages(), 0u);
}

TEST(Device, AliasingHoldsWithTheDevicesOwnMemoryRequirements) {
  Engine e;
  e.executor.configure(core_demo(), 200, 100);
  const auto& plan = e.executor.plan();
  EXPECT_LT(plan.transient_bytes_aliased, plan.transient_bytes_unaliased);
  const auto& hdr = plan.resources[static_cast<size_t>(plan.find_resource("hdr"))];
  const auto& blurred = plan.resources[static_cast<size_t>(plan.find_resource("blurred"))];
  EXPECT_EQ(hdr.block, blurred.block);
  EXPECT_EQ(hdr.offset, blurred.offset);
  // The culled preview pass gets no memory at all.
  EXPECT_FALSE(plan.resources[static_cast<size_t>(plan.find_resource("preview"))].used());
  e.executor.run_frame(true);
  EXPECT_EQ(e.vk.validation_messages(), 0u);
}

TEST(Device, TraceHasGpuAndCpuTracksAndCounters) {
  Engine e;
  e.executor.configure(core_demo(), 64, 48);
  graph::RunRecord run;
  run.device = e.vk.device_name();
  for (int f = 0; f < 3; ++f) {
    run.frame_start_ms.push_back(10.0 * f);
    run.frames.push_back(e.executor.run_frame(false));
  }
  auto trace = nlohmann::json::parse(graph::chrome_trace_json(e.executor.plan(), run).dump());
  int gpu_pass_events = 0, cpu_pass_events = 0, counters = 0;
  for (const auto& ev : trace["traceEvents"]) {
    if (ev["ph"] == "X" && ev["name"] == "blur_x") (ev["tid"] == 1 ? gpu_pass_events : cpu_pass_events)++;
    if (ev["ph"] == "C" && ev["name"] == "tonemap.bright_pixels") ++counters;
  }
  EXPECT_EQ(gpu_pass_events, 3);
  EXPECT_EQ(cpu_pass_events, 3);
  EXPECT_EQ(counters, 3);
  auto stats = graph::stats_json(e.executor.plan(), run);
  EXPECT_EQ(stats["passes"].size(), 4u);
  EXPECT_EQ(stats["frames_timed"], 2);
}

TEST(Shaders, EveryShaderCompiles) {
  shader::ShaderCompiler compiler(data_dir() / "shaders");
  int compiled = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(compiler.root())) {
    auto ext = entry.path().extension();
    if (ext != ".vert" && ext != ".frag" && ext != ".comp" && ext != ".geom") continue;
    auto relative = std::filesystem::relative(entry.path(), compiler.root()).string();
    EXPECT_NO_THROW(EXPECT_FALSE(compiler.compile(relative).empty())) << relative;
    ++compiled;
  }
  EXPECT_GE(compiled, 4);
}

TEST(Shaders, ErrorsNameFileAndLineAndTheCacheSeesIncludes) {
  auto root = std::filesystem::temp_directory_path() / ("caustica_shader_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(root / "lib");
  auto write = [&](const std::string& name, const std::string& text) { std::ofstream(root / name) << text; };
  write("lib/value.glsl", "float value() { return 1.0; }\n");
  write("ok.comp",
        "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"lib/value.glsl\"\n"
        "layout(local_size_x = 1) in;\nlayout(binding = 0) buffer B { float v[]; };\nvoid main() { v[0] = value() * SCALE; }\n");
  write("broken.comp", "#version 460\nlayout(local_size_x = 1) in;\nvoid main() {\n  undeclared_thing = 1;\n}\n");
  shader::ShaderCompiler compiler(root);
  try {
    compiler.compile("broken.comp");
    FAIL() << "a broken shader compiled";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.comp:4:"), std::string::npos) << e.what();
  }
  compiler.compile("ok.comp", {{"SCALE", "2.0"}});
  compiler.compile("ok.comp", {{"SCALE", "2.0"}});
  EXPECT_EQ(compiler.stats().compiles, 1u);
  EXPECT_EQ(compiler.stats().cache_hits, 1u);
  compiler.compile("ok.comp", {{"SCALE", "3.0"}});  // other defines: another entry
  EXPECT_EQ(compiler.stats().compiles, 2u);
  write("lib/value.glsl", "float value() { return 2.0; }\n");  // an edited include invalidates
  compiler.compile("ok.comp", {{"SCALE", "2.0"}});
  EXPECT_EQ(compiler.stats().compiles, 3u);
  std::filesystem::remove_all(root);
}

// A pipeline laid out from its shader's declarations is written by name (vk::DescriptorWriter):
// before any descriptor reaches the device, a name the shader does not declare, a resource of the
// wrong kind and a declared binding left unwritten are refused, naming the pass, shader and variable.
TEST(Shaders, DescriptorsAreWrittenByTheNamesTheShaderDeclares) {
  Engine e;
  const shader::ReflectedShader blur = e.shaders.compile_reflected("core/box_blur.comp");
  auto interface = std::make_shared<const shader::ShaderInterface>(
      "blur_x", std::vector<shader::NamedReflection>{{"core/box_blur.comp", &blur.reflection}});
  const vk::Pipeline pipeline = vk::make_compute_pipeline(e.vk, vk::reflected_desc("box_blur", interface), blur.spirv);
  const auto refusal = [&](const vk::DescriptorWriter& writer) {
    try {
      writer.push(e.vk, VK_NULL_HANDLE, pipeline);  // refused before it records anything
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("(not refused)");
  };
  const std::string misnamed =
      refusal(vk::DescriptorWriter().image("sourse", VK_NULL_HANDLE, VK_NULL_HANDLE).image("target", VK_NULL_HANDLE));
  EXPECT_NE(misnamed.find("pass 'blur_x' binds 'sourse', which its shaders (core/box_blur.comp) do not declare"), std::string::npos)
      << misnamed;
  const std::string kind = refusal(vk::DescriptorWriter().image("source", VK_NULL_HANDLE).image("target", VK_NULL_HANDLE));
  EXPECT_NE(kind.find("'source' is a sampled image (sampler2D), and the pass binds a storage image (image2D) to it"), std::string::npos)
      << kind;
  const std::string unwritten = refusal(vk::DescriptorWriter().image("source", VK_NULL_HANDLE, VK_NULL_HANDLE));
  EXPECT_NE(unwritten.find("pass 'blur_x', shader core/box_blur.comp: declares 'target' (binding 1), which the pass leaves unbound"),
            std::string::npos)
      << unwritten;
}
