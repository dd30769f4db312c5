#pragma once
// How the editor wires a pass it adds (GraphModel::add_pass): each input bound to a resource that
// a pass already writes, each output to a new resource, tried in order until the graph compiles.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "graph/pass_type.h"

namespace caustica::editor {

// Pass `pass` of `doc` made once per `kind` ("light" or "caustic_view": "for_each"), or once again
// (""): the resources it writes with it, and its "light" parameter, where its type (`type`, if
// known) has one, following its instance's light or view ("$light").
void wire_for_each(nlohmann::ordered_json& doc, nlohmann::ordered_json& pass, const graph::PassTypeDecl* type, std::string_view kind);

class PassWiring {
 public:
  // The candidates for each of `decl`'s inputs in `doc`, for a pass named `name`. Throws
  // InputError, naming `path`, when an input has none.
  PassWiring(const nlohmann::ordered_json& doc, const graph::PassTypeDecl& decl, std::string name, const std::string& path);

  // Calls `accept` with `doc` and `pass` wired, one choice of inputs after another (at most
  // kMaxTries), until it returns true; false when none was accepted. Inputs of one extent group
  // take resources of one size.
  bool try_each(const nlohmann::ordered_json& pass, const std::function<bool(nlohmann::ordered_json next)>& accept) const;

  static constexpr int kMaxTries = 64;

 private:
  // A new resource for each output, of the size of an input in the same extent group if there is
  // one; returns the outputs' bindings.
  nlohmann::ordered_json outputs_for(const std::vector<std::string>& chosen, nlohmann::ordered_json& new_resources) const;
  // The graph with the pass added and wired to `chosen`.
  nlohmann::ordered_json wired(const nlohmann::ordered_json& pass, const std::vector<std::string>& chosen) const;
  std::string size_of(const std::string& resource) const;

  const nlohmann::ordered_json& doc_;
  const nlohmann::ordered_json& resources_;
  const graph::PassTypeDecl& decl_;
  std::string name_;
  std::vector<const graph::PortDecl*> inputs_;
  std::vector<std::vector<std::string>> candidates_;
};

}  // namespace caustica::editor
