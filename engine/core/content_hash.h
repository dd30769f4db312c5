#pragma once
// FNV-1a over the bytes of values: a key for content (a mesh, a scene) that cannot go stale the way
// a path or a time can. Only for values without padding (numbers, glm vectors and matrices), whose
// bytes are their whole content.
#include <cstdint>
#include <type_traits>
#include <vector>

namespace caustica {

class ContentHash {
 public:
  void bytes(const void* data, size_t size) {
    for (size_t i = 0; i < size; ++i) hash_ = (hash_ ^ static_cast<const unsigned char*>(data)[i]) * 1099511628211ull;
  }
  template <typename T>
  void add(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>, "only plain values");
    bytes(&value, sizeof(T));
  }
  // Its length too, so that two vectors' contents cannot run into each other.
  template <typename T>
  void add(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>, "only plain values");
    add(values.size());
    bytes(values.data(), values.size() * sizeof(T));
  }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 1469598103934665603ull;
};

}  // namespace caustica
