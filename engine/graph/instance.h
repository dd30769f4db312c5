#pragma once
// Which instance of a per-light or per-view pass or resource (graph/per_light.h) a compiled one is.
namespace caustica::graph {

struct Instance {
  int light = -1;  // its light: light K's instance, or the light of caustic view `view`
  int view = -1;   // a "for_each": "caustic_view" instance's view (scene::caustic_views)
  bool any() const { return light >= 0; }
  // What "$light" and "light.index" are in it: the view's index (FrameData::caustic_lights) or the light's.
  int index() const { return view >= 0 ? view : light; }
  bool operator==(const Instance&) const = default;
};

}  // namespace caustica::graph
