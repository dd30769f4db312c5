#include "graph/result_identity.h"

#include "core/content_hash.h"

namespace caustica::graph {

ResultIdentity::ResultIdentity(std::string description, std::vector<ResultIdentity> inputs) {
  ContentHash hash;
  hash.bytes(description.data(), description.size());
  hash.add(inputs.size());
  for (const ResultIdentity& input : inputs) hash.add(input.hash());
  node_ = std::make_shared<const Node>(Node{std::move(description), std::move(inputs), hash.value()});
}

bool ResultIdentity::operator==(const ResultIdentity& other) const {
  if (node_ == other.node_) return true;
  if (node_->hash != other.node_->hash || node_->description != other.node_->description) return false;
  return node_->inputs == other.node_->inputs;
}

}  // namespace caustica::graph
