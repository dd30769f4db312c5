#include "scene/bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>

#include "common/scene_types.h"  // the instance masks

static_assert(caustica::scene::kBvhMaxDepth == CAUSTICA_BVH_MAX_DEPTH, "the shader's stack is the deepest tree's");

namespace caustica::scene {
namespace {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
  void grow(glm::vec3 p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  float half_area() const {
    if (empty()) return 0.0f;
    const glm::vec3 e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// A triangle while building: its box, centroid and mask, and where it came from.
struct Item {
  Box box;
  glm::vec3 centroid;
  uint32_t mask, input;
};

// A child as its parent stores it.
struct Child {
  Box box;
  uint32_t link = 0, info = 0;
};

constexpr uint32_t kBins = 16;
constexpr uint32_t kMaxLeaf = 8;   // the most triangles a leaf takes where the heuristic prefers it
constexpr float kNodeCost = 1.0f;  // a node's two box tests, against one triangle test
constexpr uint32_t kInstanceMaskBits = 0xFFu;

class Builder {
 public:
  explicit Builder(std::vector<BvhInputTriangle> input) : input_(std::move(input)) {
    items_.reserve(input_.size());
    for (uint32_t i = 0; i < input_.size(); ++i) {
      const BvhInputTriangle& t = input_[i];
      Item item{};
      item.box.grow(t.v0);
      item.box.grow(t.v1);
      item.box.grow(t.v2);
      item.centroid = (t.v0 + t.v1 + t.v2) / 3.0f;
      item.mask = t.flags & kInstanceMaskBits;
      item.input = i;
      items_.push_back(item);
    }
  }

  TracerBvh build() {
    // The root is node 0: build_range makes it first, unless the whole tree is one leaf, which
    // then takes node 0's first child beside an empty one.
    if (!items_.empty()) {
      const Child root = build_range(0, static_cast<uint32_t>(items_.size()), 1);
      if (nodes_.empty()) nodes_.push_back({root, Child{}});
    } else {
      nodes_.emplace_back();
    }
    return layout();
  }

 private:
  using Node = std::array<Child, 2>;

  Child leaf(uint32_t begin, uint32_t end) {
    Child c;
    c.link = static_cast<uint32_t>(order_.size());
    for (uint32_t i = begin; i < end; ++i) {
      c.box.grow(items_[i].box);
      c.info |= items_[i].mask;
      order_.push_back(items_[i].input);
    }
    c.info |= (end - begin) << 8;
    ++leaves_;
    return c;
  }

  // The best binned split of [begin, end) on the centroids' longest axis: its cost relative to one
  // triangle test, and the partition point after reordering; end when no split separates them.
  std::pair<float, uint32_t> split(uint32_t begin, uint32_t end, const Box& bounds) {
    Box centroids;
    for (uint32_t i = begin; i < end; ++i) centroids.grow(items_[i].centroid);
    const glm::vec3 extent = centroids.hi - centroids.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    if (!(extent[axis] > 0.0f)) return {0.0f, end};
    const float scale = static_cast<float>(kBins) / extent[axis];
    const auto bin_of = [&](const Item& item) {
      return std::min(kBins - 1, static_cast<uint32_t>((item.centroid[axis] - centroids.lo[axis]) * scale));
    };
    std::array<Box, kBins> boxes{};
    std::array<uint32_t, kBins> counts{};
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t b = bin_of(items_[i]);
      boxes[b].grow(items_[i].box);
      ++counts[b];
    }
    // Sweep from the right for the right sides' costs, then from the left for the best plane.
    std::array<float, kBins> right_cost{};
    Box right;
    uint32_t right_count = 0;
    for (uint32_t b = kBins - 1; b > 0; --b) {
      right.grow(boxes[b]);
      right_count += counts[b];
      right_cost[b] = right.half_area() * static_cast<float>(right_count);
    }
    Box left;
    uint32_t left_count = 0, best_plane = 0;
    float best = std::numeric_limits<float>::max();
    for (uint32_t b = 1; b < kBins; ++b) {
      left.grow(boxes[b - 1]);
      left_count += counts[b - 1];
      const float cost = left.half_area() * static_cast<float>(left_count) + right_cost[b];
      if (left_count > 0 && left_count < end - begin && cost < best) {
        best = cost;
        best_plane = b;
      }
    }
    if (best_plane == 0) return {0.0f, end};
    const auto middle =
        std::partition(items_.begin() + begin, items_.begin() + end, [&](const Item& item) { return bin_of(item) < best_plane; });
    return {kNodeCost + best / std::max(bounds.half_area(), std::numeric_limits<float>::min()),
            static_cast<uint32_t>(middle - items_.begin())};
  }

  Child build_range(uint32_t begin, uint32_t end, uint32_t depth) {
    depth_ = std::max(depth_, depth);
    const uint32_t count = end - begin;
    if (count <= 2 || depth >= kBvhMaxDepth) return leaf(begin, end);
    Box bounds;
    for (uint32_t i = begin; i < end; ++i) bounds.grow(items_[i].box);
    auto [cost, middle] = split(begin, end, bounds);
    if (middle == end) {
      if (count <= kMaxLeaf) return leaf(begin, end);
      // Centroids that no plane separates (one point, or one bin): halve the list, so the tree
      // still ends.
      middle = begin + count / 2;
    } else if (count <= kMaxLeaf && cost >= static_cast<float>(count)) {
      return leaf(begin, end);
    }
    const uint32_t node = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    const Child a = build_range(begin, middle, depth + 1);
    const Child b = build_range(middle, end, depth + 1);
    nodes_[node] = {a, b};
    Child c;
    c.box = a.box;
    c.box.grow(b.box);
    c.link = node;
    c.info = (a.info | b.info) & kInstanceMaskBits;
    return c;
  }

  TracerBvh layout() const {
    TracerBvh bvh;
    bvh.node_count = static_cast<uint32_t>(nodes_.size());
    bvh.triangle_count = static_cast<uint32_t>(order_.size());
    bvh.depth = depth_;
    bvh.leaf_count = leaves_;
    const uint32_t base = 1 + 4 * bvh.node_count;
    bvh.words.reserve(base + 3 * size_t{bvh.triangle_count});
    bvh.words.emplace_back(std::bit_cast<float>(base), 0.0f, 0.0f, 0.0f);
    for (const Node& node : nodes_) {
      for (const Child& c : node) {
        bvh.words.emplace_back(c.box.lo, std::bit_cast<float>(c.link));
        bvh.words.emplace_back(c.box.hi, std::bit_cast<float>(c.info));
      }
    }
    bvh.triangle_vertices.reserve(3 * size_t{bvh.triangle_count});
    for (uint32_t input : order_) {
      const BvhInputTriangle& t = input_[input];
      bvh.words.emplace_back(t.v0, std::bit_cast<float>(t.flags));
      bvh.words.emplace_back(t.v1, 0.0f);
      bvh.words.emplace_back(t.v2, 0.0f);
      bvh.triangle_vertices.insert(bvh.triangle_vertices.end(), t.vertices, t.vertices + 3);
    }
    return bvh;
  }

  std::vector<BvhInputTriangle> input_;
  std::vector<Item> items_;
  std::vector<Node> nodes_;
  std::vector<uint32_t> order_;  // the input triangle at each stored place
  uint32_t depth_ = 0, leaves_ = 0;
};

}  // namespace

uint32_t TracerBvh::first_triangle_word() const {
  return words.empty() ? 0 : std::bit_cast<uint32_t>(words[0].x);
}

TracerBvh build_bvh(std::vector<BvhInputTriangle> triangles) {
  return Builder(std::move(triangles)).build();
}

TracerBvh build_scene_bvh(const Scene& scene, const std::vector<uint32_t>& vertex_base) {
  std::vector<BvhInputTriangle> triangles;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    const Object& object = scene.objects[o];
    const Mesh& mesh = object.mesh;
    const uint32_t flags = (object.material.refractor ? CAUSTICA_REFRACTOR_INSTANCES : CAUSTICA_RECEIVER_INSTANCES) |
                           (object.material.alpha_mode == AlphaMode::mask ? kBvhMaskedMaterial : 0u);
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const uint32_t* v = &mesh.indices[i];
      triangles.push_back({mesh.positions[v[0]],
                           mesh.positions[v[1]],
                           mesh.positions[v[2]],
                           flags,
                           {vertex_base[o] + v[0], vertex_base[o] + v[1], vertex_base[o] + v[2]}});
    }
  }
  return build_bvh(std::move(triangles));
}

std::string check_bvh(const TracerBvh& bvh, uint32_t triangle_count) {
  if (bvh.words.empty()) return "no words";
  const uint32_t base = bvh.first_triangle_word();
  if (base != 1 + 4 * bvh.node_count) return "the triangles start at word " + std::to_string(base) + ", not after the nodes";
  if (bvh.triangle_count != triangle_count || bvh.words.size() != base + 3 * size_t{triangle_count})
    return "holds " + std::to_string(bvh.triangle_count) + " triangles, not " + std::to_string(triangle_count);
  std::vector<uint32_t> stored(triangle_count, 0);
  std::vector<bool> reached(bvh.node_count, false);
  // What lies beneath a child: its box and mask, found by walking it.
  struct Walk {
    const TracerBvh& bvh;
    uint32_t base;
    std::vector<uint32_t>& stored;
    std::vector<bool>& reached;
    std::string error;
    Box box_of(uint32_t link, uint32_t info, uint32_t depth, uint32_t& mask) {
      Box box;
      if (!error.empty()) return box;
      if (depth > kBvhMaxDepth) error = "deeper than " + std::to_string(kBvhMaxDepth);
      const uint32_t count = info >> 8;
      if (count > 0) {
        for (uint32_t t = link; t < link + count && error.empty(); ++t) {
          if (t >= stored.size()) {
            error = "a leaf reaches triangle " + std::to_string(t) + ", past the last";
            break;
          }
          ++stored[t];
          for (int k = 0; k < 3; ++k) box.grow(glm::vec3(bvh.words[base + 3 * size_t{t} + k]));
          mask |= std::bit_cast<uint32_t>(bvh.words[base + 3 * size_t{t}].w) & kInstanceMaskBits;
        }
        return box;
      }
      if (link >= reached.size() || reached[link]) {
        error = "node " + std::to_string(link) + (link >= reached.size() ? " does not exist" : " is reached twice");
        return box;
      }
      reached[link] = true;
      for (uint32_t c = 0; c < 2 && error.empty(); ++c) {
        const glm::vec4 lo = bvh.words[1 + 4 * size_t{link} + 2 * c], hi = bvh.words[2 + 4 * size_t{link} + 2 * c];
        if (std::bit_cast<uint32_t>(hi.w) == 0 && lo.x > hi.x) continue;  // empty
        uint32_t below = 0;
        const Box inner = box_of(std::bit_cast<uint32_t>(lo.w), std::bit_cast<uint32_t>(hi.w), depth + 1, below);
        if (!error.empty()) break;
        if (!inner.empty() && (glm::any(glm::lessThan(glm::vec3(hi), inner.hi)) || glm::any(glm::greaterThan(glm::vec3(lo), inner.lo))))
          error = "node " + std::to_string(link) + "'s child " + std::to_string(c) + " has a box that does not hold what lies beneath it";
        else if ((std::bit_cast<uint32_t>(hi.w) & kInstanceMaskBits) != below)
          error = "node " + std::to_string(link) + "'s child " + std::to_string(c) + " has mask " +
                  std::to_string(std::bit_cast<uint32_t>(hi.w) & kInstanceMaskBits) + ", not its triangles' " + std::to_string(below);
        box.grow(inner);
        mask |= below;
      }
      return box;
    }
  } walk{bvh, base, stored, reached, {}};
  uint32_t mask = 0;
  walk.box_of(0, 0, 0, mask);
  if (!walk.error.empty()) return walk.error;
  for (uint32_t t = 0; t < triangle_count; ++t) {
    if (stored[t] != 1) return "triangle " + std::to_string(t) + " is in " + std::to_string(stored[t]) + " leaves";
  }
  for (uint32_t n = 0; n < bvh.node_count; ++n) {
    if (!reached[n]) return "node " + std::to_string(n) + " is reached from no parent";
  }
  return "";
}

}  // namespace caustica::scene
