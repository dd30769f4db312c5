// The compute tracer's BVH (engine/scene/bvh.h) on the CPU: the builder's trees against check_bvh,
// the checker against trees broken on purpose, and a walk of the words as the layout documents
// them against testing every triangle. The shader's walk of it is tested on the device
// (tracer_test.cpp).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <random>

#include "common/scene_types.h"
#include "scene/bvh.h"

using namespace caustica;
using scene::BvhInputTriangle;
using scene::TracerBvh;

namespace {

// `count` small triangles scattered in a unit cube, every third a refractor's, each carrying its
// input index as its first vertex.
std::vector<BvhInputTriangle> soup(uint32_t count, uint32_t seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), small(-0.03f, 0.03f);
  std::vector<BvhInputTriangle> triangles;
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 c(unit(rng), unit(rng), unit(rng));
    const uint32_t mask = i % 3 == 0 ? CAUSTICA_REFRACTOR_INSTANCES : CAUSTICA_RECEIVER_INSTANCES;
    triangles.push_back({c + glm::vec3(small(rng), small(rng), small(rng)),
                         c + glm::vec3(small(rng), small(rng), small(rng)),
                         c + glm::vec3(small(rng), small(rng), small(rng)),
                         mask,
                         {i, 0, 0}});
  }
  return triangles;
}

// The nearest triangle that a ray meets (Moller-Trumbore, the same test for both walks), and its distance.
struct Hit {
  int32_t input = -1;
  float t = INFINITY;
};

bool meets(glm::vec3 o, glm::vec3 d, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, float& t) {
  const glm::vec3 e1 = v1 - v0, e2 = v2 - v0, p = glm::cross(d, e2);
  const float det = glm::dot(e1, p);
  if (std::abs(det) < 1e-12f) return false;
  const glm::vec3 s = o - v0, q = glm::cross(s, e1);
  const float u = glm::dot(s, p) / det, v = glm::dot(d, q) / det;
  t = glm::dot(e2, q) / det;
  return u >= 0 && v >= 0 && u + v <= 1 && t > 0;
}

Hit every_triangle(const std::vector<BvhInputTriangle>& triangles, glm::vec3 o, glm::vec3 d, uint32_t mask) {
  Hit best;
  for (const auto& tri : triangles) {
    float t = 0;
    if ((tri.flags & mask) != 0 && meets(o, d, tri.v0, tri.v1, tri.v2, t) && t < best.t) best = {static_cast<int32_t>(tri.vertices[0]), t};
  }
  return best;
}

// The BVH's words read as bvh.h documents them: a stack of nodes, boxes by slabs, masks per child.
Hit walk(const TracerBvh& bvh, glm::vec3 o, glm::vec3 d, uint32_t mask) {
  Hit best;
  const uint32_t base = bvh.first_triangle_word();
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 0}};  // (link, count) of children to visit
  while (!stack.empty()) {
    const auto [link, count] = stack.back();
    stack.pop_back();
    if (count > 0) {
      for (uint32_t t = link; t < link + count; ++t) {
        const glm::vec4* w = &bvh.words[base + 3 * size_t{t}];
        float hit_t = 0;
        if ((std::bit_cast<uint32_t>(w[0].w) & mask) != 0 && meets(o, d, w[0], w[1], w[2], hit_t) && hit_t < best.t)
          best = {static_cast<int32_t>(bvh.triangle_vertices[3 * size_t{t}]), hit_t};
      }
      continue;
    }
    for (uint32_t c = 0; c < 2; ++c) {
      const glm::vec4 lo = bvh.words[1 + 4 * size_t{link} + 2 * c], hi = bvh.words[2 + 4 * size_t{link} + 2 * c];
      if ((std::bit_cast<uint32_t>(hi.w) & mask) == 0) continue;
      const glm::vec3 t0 = (glm::vec3(lo) - o) / d, t1 = (glm::vec3(hi) - o) / d;
      const glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
      if (std::max({near.x, near.y, near.z, 0.0f}) > std::min({far.x, far.y, far.z, best.t})) continue;
      stack.emplace_back(std::bit_cast<uint32_t>(lo.w), std::bit_cast<uint32_t>(hi.w) >> 8);
    }
  }
  return best;
}

}  // namespace

// Every tree the builder makes passes the checker: scattered triangles of every count up to
// thousands, one triangle, none, and thousands on one spot (no plane separates them; the tree must
// still end, within kBvhMaxDepth).
TEST(Bvh, EveryTriangleIsStoredOnceUnderBoxesThatHoldIt) {
  for (uint32_t count : {0u, 1u, 2u, 3u, 9u, 100u, 5000u}) {
    const TracerBvh bvh = scene::build_bvh(soup(count));
    EXPECT_EQ(scene::check_bvh(bvh, count), "") << count << " triangles";
  }
  std::vector<BvhInputTriangle> stacked(3000, BvhInputTriangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, CAUSTICA_RECEIVER_INSTANCES, {}});
  const TracerBvh bvh = scene::build_bvh(stacked);
  EXPECT_EQ(scene::check_bvh(bvh, 3000), "");
  EXPECT_LE(bvh.depth, scene::kBvhMaxDepth);
}

// The surface-area heuristic's tree over scattered triangles: small leaves, a depth near log2 of
// the count (a median split of 8000 triangles in leaves of 8 is 10 deep; 16 when this was written).
TEST(Bvh, TheTreeIsShallowWithSmallLeaves) {
  const TracerBvh bvh = scene::build_bvh(soup(8000));
  ASSERT_EQ(scene::check_bvh(bvh, 8000), "");
  std::printf("8000 triangles: %u nodes, %u leaves, depth %u\n", bvh.node_count, bvh.leaf_count, bvh.depth);
  EXPECT_LE(bvh.depth, 26u);
  EXPECT_GE(bvh.leaf_count, 8000u / 8);
}

// The checker finds each way a tree can be wrong: a leaf that lost a triangle, a box that does not
// hold its children, a child that points at another's node, and a mask that lost a bit.
TEST(Bvh, TheCheckFindsEachBreakage) {
  const TracerBvh good = scene::build_bvh(soup(300));
  ASSERT_EQ(scene::check_bvh(good, 300), "");
  // The first child that is a leaf of two triangles or more (one that loses one stays a leaf), or
  // an inner one: its words.
  const auto child_words = [&](bool leaf) {
    for (uint32_t n = 0; n < good.node_count; ++n) {
      for (uint32_t c = 0; c < 2; ++c) {
        const size_t lo = 1 + 4 * size_t{n} + 2 * c;
        const uint32_t count = std::bit_cast<uint32_t>(good.words[lo + 1].w) >> 8;
        if (leaf ? count >= 2 : count == 0) return lo;
      }
    }
    ADD_FAILURE() << "no such child";
    return size_t{1};
  };
  TracerBvh missing = good;
  const size_t leaf = child_words(true);
  missing.words[leaf + 1].w = std::bit_cast<float>(std::bit_cast<uint32_t>(missing.words[leaf + 1].w) - (1u << 8));
  EXPECT_NE(scene::check_bvh(missing, 300).find("is in 0 leaves"), std::string::npos) << scene::check_bvh(missing, 300);

  TracerBvh shrunk = good;
  shrunk.words[leaf + 1].x -= 0.01f;  // the leaf's box short of its triangles
  EXPECT_NE(scene::check_bvh(shrunk, 300).find("does not hold"), std::string::npos) << scene::check_bvh(shrunk, 300);

  TracerBvh redirected = good;
  const size_t inner = child_words(false);
  redirected.words[inner].w = std::bit_cast<float>(std::bit_cast<uint32_t>(redirected.words[inner].w) == 1 ? 2 : 1);
  const std::string skipped = scene::check_bvh(redirected, 300);
  // The subtree it left is nobody's child, and its triangles in no leaf, unless the walk meets its
  // new one twice first.
  EXPECT_TRUE(skipped.find("reached twice") != std::string::npos || skipped.find("from no parent") != std::string::npos ||
              skipped.find("in 0 leaves") != std::string::npos)
      << skipped;

  TracerBvh unmasked = good;
  unmasked.words[inner + 1].w = std::bit_cast<float>(std::bit_cast<uint32_t>(unmasked.words[inner + 1].w) & ~CAUSTICA_REFRACTOR_INSTANCES);
  EXPECT_NE(scene::check_bvh(unmasked, 300).find("has mask"), std::string::npos) << scene::check_bvh(unmasked, 300);
}

// Walking the words as documented finds, for 5000 random rays with each mask, the triangle that
// testing every triangle finds: the layout says what the builder wrote.
TEST(Bvh, AWalkOfTheLayoutFindsTheNearestTriangle) {
  const std::vector<BvhInputTriangle> triangles = soup(1000, 7);
  const TracerBvh bvh = scene::build_bvh(triangles);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), signed_unit(-1.0f, 1.0f);
  uint32_t hits = 0;
  for (int r = 0; r < 5000; ++r) {
    const glm::vec3 o(unit(rng), unit(rng), -0.5f);
    const glm::vec3 d = glm::normalize(glm::vec3(0.3f * signed_unit(rng), 0.3f * signed_unit(rng), 1.0f));
    const uint32_t mask = r % 3 == 0 ? CAUSTICA_RECEIVER_INSTANCES : CAUSTICA_ALL_INSTANCES;
    const Hit expected = every_triangle(triangles, o, d, mask), found = walk(bvh, o, d, mask);
    ASSERT_EQ(found.input, expected.input) << "ray " << r;
    hits += expected.input >= 0 ? 1 : 0;
  }
  EXPECT_GT(hits, 300u);  // the rays meet triangles, so the comparison says something
}
