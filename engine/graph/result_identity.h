#pragma once
// What a pass's result follows from besides the scene: its own description (name, type, parameters,
// its ports' formats and extents, its shader's text) and the identities of what it reads. Two plans'
// passes with equal identities compute the same images from the same scene, so a result can go from
// one plan to the next (Executor: the hand-over of a plan change).
//
// Equality is exact: the descriptions and the inputs' identities are compared, not only a hash of
// them, so that two different results can never be taken for one. The hash only makes most
// comparisons of different identities cheap.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace caustica::graph {

class ResultIdentity {
 public:
  ResultIdentity(std::string description, std::vector<ResultIdentity> inputs);
  bool operator==(const ResultIdentity& other) const;
  uint64_t hash() const { return node_->hash; }

 private:
  struct Node {
    std::string description;
    std::vector<ResultIdentity> inputs;
    uint64_t hash = 0;
  };
  std::shared_ptr<const Node> node_;  // shared: a plan's identities refer to those of earlier passes
};

}  // namespace caustica::graph
