// Whether a mesh bounds a convex solid, so that a ray leaving it cannot meet it again. A closed,
// connected surface that is convex at every edge bounds a convex body (Tietze's theorem for an
// embedded surface); a check of every vertex against every face plane then rules out a surface that
// only seems so because it overlaps itself.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>
#include <unordered_map>

#include "core/content_hash.h"
#include "scene/scene.h"

namespace caustica::scene {

namespace {

// One index per distinct position: vertices closer than `tolerance` are one (split vertices at
// creases and texture seams, and a primitive's seam, whose ends differ by float rounding). Cells of
// the tolerance's size, counted from the corner `low` of the bounds (so that the counts stay within
// an int wherever the mesh lies), are hashed, and the 27 around a position are searched.
struct Welded {
  std::vector<uint32_t> index;     // per position: its welded vertex
  std::vector<uint32_t> position;  // per welded vertex: its first position
};

Welded weld(const std::vector<glm::vec3>& positions, glm::vec3 low, float tolerance) {
  auto cell_of = [&](const glm::vec3& p) { return glm::ivec3(glm::floor((p - low) / tolerance)); };
  auto key = [](glm::ivec3 c) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(c.x)) * 73856093u) ^
           (static_cast<uint64_t>(static_cast<uint32_t>(c.y)) * 19349663u) ^
           (static_cast<uint64_t>(static_cast<uint32_t>(c.z)) * 83492791u);
  };
  std::unordered_multimap<uint64_t, uint32_t> cells;  // cell -> welded vertex
  Welded w{std::vector<uint32_t>(positions.size()), {}};
  for (size_t i = 0; i < positions.size(); ++i) {
    const glm::ivec3 cell = cell_of(positions[i]);
    int64_t found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          auto [from, to] = cells.equal_range(key(cell + glm::ivec3(dx, dy, dz)));
          for (auto it = from; it != to; ++it) {
            if (glm::length(positions[w.position[it->second]] - positions[i]) <= tolerance) {
              found = it->second;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int64_t>(w.position.size());
      w.position.push_back(static_cast<uint32_t>(i));
      cells.emplace(key(cell), static_cast<uint32_t>(found));
    }
    w.index[i] = static_cast<uint32_t>(found);
  }
  return w;
}

// Vertices in clusters of nearby ones, each with a bounding sphere, so that a plane can clear a
// whole cluster at once: split at the median of the longest axis until a cluster is small.
struct Cluster {
  glm::vec3 center;
  float radius;
  size_t first, count;  // into VertexClusters::order
};
struct VertexClusters {
  std::vector<uint32_t> order;  // vertex indices, each cluster's contiguous
  std::vector<Cluster> clusters;
};

void split_clusters(const std::vector<glm::vec3>& positions, size_t first, size_t count, VertexClusters& out) {
  auto begin = out.order.begin() + static_cast<std::ptrdiff_t>(first);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (auto it = begin; it != begin + static_cast<std::ptrdiff_t>(count); ++it) {
    lo = glm::min(lo, positions[*it]);
    hi = glm::max(hi, positions[*it]);
  }
  constexpr size_t kLeaf = 32;
  if (count <= kLeaf) {
    const glm::vec3 center = 0.5f * (lo + hi);
    float radius = 0.0f;
    for (auto it = begin; it != begin + static_cast<std::ptrdiff_t>(count); ++it)
      radius = std::max(radius, glm::length(positions[*it] - center));
    out.clusters.push_back({center, radius, first, count});
    return;
  }
  const glm::vec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const size_t half = count / 2;
  std::nth_element(begin, begin + static_cast<std::ptrdiff_t>(half), begin + static_cast<std::ptrdiff_t>(count),
                   [&](uint32_t a, uint32_t b) { return positions[a][axis] < positions[b][axis]; });
  split_clusters(positions, first, half, out);
  split_clusters(positions, first + half, count - half, out);
}

VertexClusters cluster_vertices(const std::vector<glm::vec3>& positions) {
  VertexClusters out;
  for (uint32_t i = 0; i < positions.size(); ++i) out.order.push_back(i);
  split_clusters(positions, 0, positions.size(), out);
  return out;
}

uint32_t root_of(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

bool is_convex_solid(const Mesh& mesh) {
  if (mesh.positions.empty() || mesh.indices.size() < 12) return false;
  const auto [lo, hi] = mesh_bounds(mesh);
  const float size = glm::length(hi - lo);
  if (!(size > 0.0f) || !std::isfinite(size)) return false;
  const float tolerance = 1e-5f * size;
  const Welded welded = weld(mesh.positions, lo, tolerance);

  struct Face {
    uint32_t v[3];
    glm::vec3 normal;  // unit, outward for counter-clockwise winding
    glm::vec3 point;
  };
  std::vector<Face> faces;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    Face f{{welded.index[mesh.indices[t]], welded.index[mesh.indices[t + 1]], welded.index[mesh.indices[t + 2]]},
           {},
           mesh.positions[mesh.indices[t]]};
    if (f.v[0] == f.v[1] || f.v[1] == f.v[2] || f.v[0] == f.v[2]) continue;  // collapsed by the weld: no area
    const glm::vec3 n = glm::cross(mesh.positions[mesh.indices[t + 1]] - f.point, mesh.positions[mesh.indices[t + 2]] - f.point);
    if (!(glm::length(n) > 0.0f)) continue;
    f.normal = glm::normalize(n);
    faces.push_back(f);
  }
  if (faces.size() < 4) return false;

  // Closed and consistently wound: every directed edge once, and its reverse once. A sorted array
  // rather than a map: a process that loads the 70k-triangle bunny builds this at every start.
  struct DirectedEdge {
    uint64_t key;  // from << 32 | to
    uint32_t face;
    bool operator<(const DirectedEdge& other) const { return key < other.key; }
  };
  auto edge_key = [](uint32_t from, uint32_t to) { return uint64_t{from} << 32 | to; };
  std::vector<DirectedEdge> edges;
  edges.reserve(faces.size() * 3);
  for (uint32_t i = 0; i < faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) edges.push_back({edge_key(faces[i].v[k], faces[i].v[(k + 1) % 3]), i});
  }
  std::sort(edges.begin(), edges.end());
  for (size_t e = 1; e < edges.size(); ++e) {
    if (edges[e].key == edges[e - 1].key) return false;  // a directed edge twice
  }
  std::vector<uint32_t> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const DirectedEdge& edge : edges) {
    const auto from = static_cast<uint32_t>(edge.key >> 32), to = static_cast<uint32_t>(edge.key);
    const auto twin = std::lower_bound(edges.begin(), edges.end(), DirectedEdge{edge_key(to, from), 0});
    if (twin == edges.end() || twin->key != edge_key(to, from)) return false;  // an open edge
    const Face& other = faces[twin->face];
    const Face& here = faces[edge.face];
    // Convex at the edge: the neighbour's far vertex is not in front of this face's plane.
    for (uint32_t v : other.v) {
      if (v == from || v == to) continue;
      if (glm::dot(here.normal, mesh.positions[welded.position[v]] - here.point) > tolerance) return false;
    }
    parent[root_of(parent, edge.face)] = root_of(parent, twin->face);
  }
  const uint32_t component = root_of(parent, 0);
  for (uint32_t i = 0; i < faces.size(); ++i) {
    if (root_of(parent, i) != component) return false;  // two separate bodies
  }

  // Every vertex behind every face's plane. A cluster whose bounding sphere lies behind the plane
  // needs no vertex looked at: on a convex mesh only the clusters the plane touches do.
  const VertexClusters clusters = cluster_vertices(mesh.positions);
  for (const Face& f : faces) {
    for (const Cluster& c : clusters.clusters) {
      if (glm::dot(f.normal, c.center - f.point) + c.radius <= tolerance) continue;
      for (size_t k = c.first; k < c.first + c.count; ++k) {
        if (glm::dot(f.normal, mesh.positions[clusters.order[k]] - f.point) > tolerance) return false;
      }
    }
  }
  return true;
}

bool is_convex_refractor(const Object& object) {
  if (!object.material.refractor || object.material.thin) return false;
  // Remembered by the mesh's content, so that it cannot go stale and is judged once per mesh: the
  // viewer uploads the scene again at every camera or light move, and the bunny's check takes
  // about 100 ms (its hash under 1 ms).
  ContentHash content;
  content.bytes(object.mesh.positions.data(), object.mesh.positions.size() * sizeof(glm::vec3));
  content.bytes(object.mesh.indices.data(), object.mesh.indices.size() * sizeof(uint32_t));
  const uint64_t hash = content.value();
  static std::mutex mutex;
  static std::unordered_map<uint64_t, bool> judged;
  {
    const std::lock_guard lock(mutex);
    if (const auto found = judged.find(hash); found != judged.end()) return found->second;
  }
  const bool convex = is_convex_solid(object.mesh);
  const std::lock_guard lock(mutex);
  return judged.emplace(hash, convex).first->second;
}

}  // namespace caustica::scene
