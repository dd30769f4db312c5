#pragma once
// Pass types that exist only for compiler tests: declarations without any device code.
#include "graph/pass_type.h"

namespace caustica::test {

inline graph::PassRegistry make_test_registry() {
  using namespace graph;
  PassRegistry registry;
  auto color_out = [](std::string name, bool optional = false) {
    PortDecl p{name, PortAccess::write, ResourceKind::image, PortUsage::color_attachment, {}, optional, "frame", ""};
    return p;
  };
  auto sampled_in = [](std::string name, bool optional = false) {
    return PortDecl{name, PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, optional, "", ""};
  };
  // Mode "a" draws from a light's view, "b" from the camera's (for the dependency tests).
  PassTypeDecl source{
      "source",
      "writes an image",
      PassQueue::graphics,
      {color_out("color")},
      {{"gain", ParamType::float_, 1.0, 0.0, 10.0, {}, "brightness"}, {"mode", ParamType::choice, "a", {}, {}, {"a", "b"}, ""}},
      false,
      nullptr};
  source.depends_on = [](const nlohmann::json& params) {
    return params.value("mode", "a") == "a" ? kDependsOnGeometry | kDependsOnLights : kDependsOnCamera;
  };
  registry.add(source);
  auto inputs_alone = [](const nlohmann::json&) { return 0u; };
  PassTypeDecl filter{"filter",
                      "reads one image, writes another of the same size",
                      PassQueue::compute,
                      {sampled_in("source"),
                       {"target",
                        PortAccess::write,
                        ResourceKind::image,
                        PortUsage::storage,
                        {Format::rgba16f, Format::rgba32f, Format::rgba8},
                        false,
                        "",
                        ""}},
                      {{"radius", ParamType::int_, 1, 0.0, 16.0, {}, "", true}},
                      false,
                      nullptr};
  filter.depends_on = inputs_alone;
  registry.add(filter);
  PassTypeDecl blend{"blend",
                     "two inputs into one output of the same extent",
                     PassQueue::graphics,
                     {{"a", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", ""},
                      {"b", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", ""},
                      color_out("color")},
                     {},
                     false,
                     nullptr};
  blend.depends_on = inputs_alone;
  registry.add(blend);
  registry.add({"accumulate",
                "adds into an image that another pass wrote",
                PassQueue::compute,
                {{"target", PortAccess::read_write, ResourceKind::image, PortUsage::storage, {}, false, "", ""}},
                {},
                false,
                nullptr});
  // Draws over an image that another pass wrote, from its parameter alone (reusable).
  PassTypeDecl overlay{"overlay",
                       "draws over an image",
                       PassQueue::compute,
                       {{"target", PortAccess::read_write, ResourceKind::image, PortUsage::storage, {}, false, "", ""}},
                       {{"gain", ParamType::float_, 1.0, 0.0, 10.0, {}, ""}},
                       false,
                       nullptr};
  overlay.depends_on = inputs_alone;
  registry.add(overlay);
  // A running mean over frames: its output moves each frame from its own last one.
  PassTypeDecl mean{"mean", "averages an image over frames", PassQueue::compute, {sampled_in("source"), color_out("average")}, {}, false,
                    nullptr};
  mean.accumulates = true;
  registry.add(mean);
  registry.add({"report", "reads an image and reports on it (side effect)", PassQueue::compute, {sampled_in("source")}, {}, true, nullptr});
  // Reads one image per light (a per-light port, element K light K's) and the camera's image.
  PortDecl per_light_in = sampled_in("lights", true);
  per_light_in.per_light = true;
  registry.add({"gather",
                "reads an image per light into one",
                PassQueue::graphics,
                {per_light_in, sampled_in("base"), color_out("color")},
                {},
                false,
                nullptr});
  registry.add({"splat",
                "writes an r32f array of three layers (a colour per layer) and reads it back",
                PassQueue::compute,
                {{"target", PortAccess::write, ResourceKind::image, PortUsage::storage, {Format::r32f}, false, "", "", false, 3},
                 {"color", PortAccess::write, ResourceKind::image, PortUsage::storage, {}, true, "", ""}},
                {},
                true,
                nullptr});
  // A pass with many optional ports of every kind, for randomly generated graphs.
  PassTypeDecl node{"node", "random graph node", PassQueue::compute, {}, {}, false, nullptr};
  for (int i = 0; i < 4; ++i) node.ports.push_back(sampled_in("in" + std::to_string(i), true));
  for (int i = 0; i < 2; ++i) {
    node.ports.push_back({"bin" + std::to_string(i), PortAccess::read, ResourceKind::buffer, PortUsage::storage, {}, true, "", ""});
    node.ports.push_back({"out" + std::to_string(i), PortAccess::write, ResourceKind::image, PortUsage::storage, {}, true, "", ""});
    node.ports.push_back({"bout" + std::to_string(i), PortAccess::write, ResourceKind::buffer, PortUsage::storage, {}, true, "", ""});
  }
  registry.add(node);
  return registry;
}

}  // namespace caustica::test
