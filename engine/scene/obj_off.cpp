// Wavefront OBJ and OFF (the Stanford models Debian ships).
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "scene/mesh_formats.h"

namespace caustica::scene::formats {
namespace {

// Splits a line into whitespace-separated tokens.
std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

float parse_float(std::string_view text, const std::string& path, size_t line) {
  float v = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    fail(path, line, "'" + std::string(text) + "' is not a finite number");
  }
  return v;
}

long parse_int(std::string_view text, const std::string& path, size_t line) {
  long v = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size()) fail(path, line, "'" + std::string(text) + "' is not an integer");
  return v;
}

}  // namespace

Mesh load_obj(const std::string& path, const std::string& text) {
  Mesh mesh;
  std::istringstream in(text);
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    auto t = tokens(line);
    if (t.empty() || t[0][0] == '#') continue;
    if (t[0] == "v") {
      if (t.size() < 4) fail(path, number, "a vertex needs three coordinates");
      mesh.positions.emplace_back(parse_float(t[1], path, number), parse_float(t[2], path, number), parse_float(t[3], path, number));
    } else if (t[0] == "f") {
      if (t.size() < 4) fail(path, number, "a face needs at least three vertices");
      std::vector<uint32_t> face;
      for (size_t i = 1; i < t.size(); ++i) {
        long index = parse_int(t[i].substr(0, t[i].find('/')), path, number);
        long count = static_cast<long>(mesh.positions.size());
        long resolved = index < 0 ? count + index : index - 1;  // OBJ counts from 1; negative counts back
        if (index == 0 || resolved < 0 || resolved >= count) {
          fail(path, number, "face vertex " + std::to_string(index) + " does not exist (" + std::to_string(count) + " vertices so far)");
        }
        face.push_back(static_cast<uint32_t>(resolved));
      }
      for (size_t i = 1; i + 1 < face.size(); ++i) mesh.indices.insert(mesh.indices.end(), {face[0], face[i], face[i + 1]});
    }
    // vn, vt, o, g, s, usemtl, mtllib: not needed (normals are recomputed smooth)
  }
  return mesh;
}

Mesh load_off(const std::string& path, const std::string& text) {
  Mesh mesh;
  std::istringstream in(text);
  std::string line;
  size_t number = 0;
  auto next = [&]() -> std::vector<std::string_view> {
    while (std::getline(in, line)) {
      ++number;
      auto t = tokens(line);
      if (!t.empty() && t[0][0] != '#') return t;
    }
    fail(path, number, "the file ends early");
  };
  auto header = next();
  if (header[0] != "OFF") fail(path, number, "an OFF file starts with 'OFF'");
  if (header.size() == 1)
    header = next();
  else
    header.erase(header.begin());
  if (header.size() < 2) fail(path, number, "expected vertex and face counts");
  long vertices = parse_int(header[0], path, number), faces = parse_int(header[1], path, number);
  if (vertices <= 0 || faces <= 0 || vertices > 50'000'000 || faces > 50'000'000) fail(path, number, "vertex or face count out of range");
  for (long v = 0; v < vertices; ++v) {
    auto t = next();
    if (t.size() < 3) fail(path, number, "a vertex needs three coordinates");
    mesh.positions.emplace_back(parse_float(t[0], path, number), parse_float(t[1], path, number), parse_float(t[2], path, number));
  }
  for (long f = 0; f < faces; ++f) {
    auto t = next();
    long n = parse_int(t[0], path, number);
    if (n < 3 || static_cast<size_t>(n) + 1 > t.size()) fail(path, number, "a face needs its vertex count and at least three vertices");
    std::vector<uint32_t> face;
    for (long i = 1; i <= n; ++i) {
      long index = parse_int(t[static_cast<size_t>(i)], path, number);
      if (index < 0 || index >= vertices) fail(path, number, "face vertex " + std::to_string(index) + " does not exist");
      face.push_back(static_cast<uint32_t>(index));
    }
    for (size_t i = 1; i + 1 < face.size(); ++i) mesh.indices.insert(mesh.indices.end(), {face[0], face[i], face[i + 1]});
  }
  return mesh;
}

}  // namespace caustica::scene::formats
