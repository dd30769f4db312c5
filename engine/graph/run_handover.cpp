// plan_hand_over: what goes from one realized plan to the next (engine/graph/run_policy.h).
#include <algorithm>

#include "graph/run_policy.h"

namespace caustica::graph {
namespace {

// Whether resource `a`'s image, in memory of its own, can stand for `b`'s.
bool same_own_image(const PlannedResource& a, const PlannedResource& b) {
  return a.kind == ResourceKind::image && b.kind == ResourceKind::image && !a.transient && !b.transient && a.format == b.format &&
         a.width == b.width && a.height == b.height && a.mips == b.mips && a.layers == b.layers && a.image_usage == b.image_usage;
}

// The passes of `record` set up with a saved shader file, or reading what such a pass writes: they
// compute anew.
std::vector<bool> stale_passes(const PlanRecord& record, const std::set<std::filesystem::path>& edited) {
  const Plan& plan = *record.plan;
  std::vector<bool> stale(plan.passes.size(), false);
  if (edited.empty()) return stale;
  std::set<uint32_t> recomputed;  // resources of `plan`
  for (size_t j = 0; j < plan.passes.size(); ++j) {
    const PlannedPass& pass = plan.passes[j];
    const auto& files = (*record.shader_files)[j];
    bool edited_or_reads = std::any_of(files.begin(), files.end(), [&](const std::filesystem::path& f) { return edited.count(f) != 0; });
    for (const auto& [port, resource] : pass.ports)
      edited_or_reads = edited_or_reads || (pass.decl->find_port(port)->access != PortAccess::write && recomputed.count(resource));
    if (!edited_or_reads) continue;
    stale[j] = true;
    for (const auto& [port, resource] : pass.ports) {
      if (pass.decl->find_port(port)->access != PortAccess::read) recomputed.insert(resource);
    }
  }
  return stale;
}

bool has_result(const PlanRecord& record, size_t j) {
  return j < record.state->passes.size() && record.state->passes[j].started_from.has_value();
}

bool carries_from(const HandOver& h, uint32_t from) {
  return std::any_of(h.images.begin(), h.images.end(), [&](const ImageMove& m) { return m.from == from; });
}
bool carries_to(const HandOver& h, uint32_t to) {
  return std::any_of(h.images.begin(), h.images.end(), [&](const ImageMove& m) { return m.to == to; });
}

// The refining passes of the new plan continue the running results of the plan before with an
// equal running identity, or of a plan parked since (the viewer's still plan comes back after its
// while_moving plan); the plan before's others are parked.
void continue_running_results(const PlanRecord& from, const std::vector<ResultIdentity>& parked, const Plan& after,
                              const std::vector<bool>& stale, HandOver& h) {
  std::vector<size_t> offered;
  for (size_t j = 0; j < from.plan->passes.size(); ++j) {
    if (from.plan->passes[j].running_id && !stale[j] && has_result(from, j)) offered.push_back(j);
  }
  std::vector<bool> parked_taken(parked.size(), false);
  for (size_t i = 0; i < after.passes.size(); ++i) {
    const std::optional<ResultIdentity>& id = after.passes[i].running_id;
    if (!id) continue;
    const auto found = std::find_if(offered.begin(), offered.end(), [&](size_t j) { return from.plan->passes[j].running_id == id; });
    if (found != offered.end()) {
      h.continues[i] = *found;
      offered.erase(found);
      continue;
    }
    for (size_t k = 0; k < parked.size(); ++k) {
      if (parked_taken[k] || !(parked[k] == *id)) continue;
      parked_taken[k] = true;
      h.continues_parked[i] = k;
      break;
    }
  }
  h.parks = offered;
}

// A new plan's pass with the result identity (or, showing apart, the showing identity) of a pass
// that has a result in the plan before takes its images over: handed where both plans describe an
// image alike in memory of its own (nothing to copy: about 0.1 s of copies at 1280x720 on
// lavapipe, for a still level's step), else copied. A result in a buffer is computed again.
void carry_results(const PlanRecord& from, const Plan& after, const std::vector<bool>& stale, HandOver& h) {
  const Plan& before = *from.plan;
  const auto source_of = [&](const PlannedPass& pass) -> std::optional<size_t> {
    for (size_t j = 0; j < before.passes.size(); ++j) {
      if (stale[j] || !has_result(from, j)) continue;
      if (pass.result_id && before.passes[j].result_id == pass.result_id) return j;
    }
    for (size_t j = 0; j < before.passes.size(); ++j) {
      if (stale[j] || !has_result(from, j)) continue;
      if (pass.showing_id && before.passes[j].showing_id == pass.showing_id) return j;
    }
    return std::nullopt;
  };
  for (size_t i = 0; i < after.passes.size(); ++i) {
    const PlannedPass& pass = after.passes[i];
    const std::optional<size_t> source = source_of(pass);
    if (!source) continue;
    const PlannedPass& was = before.passes[*source];
    std::vector<ImageMove> moves;
    bool images_only = true;
    for (const auto& [port, resource] : pass.ports) {
      if (pass.decl->find_port(port)->access == PortAccess::read) continue;
      images_only &= after.resources[resource].kind == ResourceKind::image;
      const uint32_t old = was.ports.at(port);
      moves.push_back({old, resource, same_own_image(before.resources[old], after.resources[resource])});
    }
    if (!images_only) continue;
    for (const ImageMove& move : moves) {
      // A resource that several carried passes write (one rewriting another's) goes over once.
      if (!carries_from(h, move.from) && !carries_to(h, move.to)) h.images.push_back(move);
    }
    h.takes_result[i] = source;
  }
}

// The plan before's picture stands in for the new showing passes' that carried none: their images
// are handed over by name, where alike.
void stand_picture(const PlanRecord& from, const Plan& after, HandOver& h) {
  const Plan& before = *from.plan;
  const auto outputs_carried = [&] { return std::all_of(after.outputs.begin(), after.outputs.end(), [&](uint32_t o) { return carries_to(h, o); }); };
  if (outputs_carried()) return;  // the showing passes carried theirs: no picture to stand in
  for (size_t i = 0; i < after.passes.size(); ++i) {
    const PlannedPass& pass = after.passes[i];
    if (pass.refines || h.takes_result[i] || h.continues[i] || h.continues_parked[i]) continue;  // refining, or its results carried over
    for (const auto& [port, resource] : pass.ports) {
      if (pass.decl->find_port(port)->access == PortAccess::read || carries_to(h, resource)) continue;
      const int was = before.find_resource(after.resources[resource].name);
      if (was < 0) continue;
      const auto old = static_cast<uint32_t>(was);
      if (!same_own_image(before.resources[old], after.resources[resource]) || carries_from(h, old)) continue;
      h.images.push_back({old, resource, true});
    }
  }
  if (outputs_carried()) h.standing = from.state->standing ? from.state->standing : from.state->last_scene;
}

}  // namespace

HandOver plan_hand_over(const PlanRecord& running_from, const PlanRecord& results_from, const std::vector<ResultIdentity>& parked,
                        const Plan& after, const HandOverOptions& options) {
  HandOver h;
  h.continues.resize(after.passes.size());
  h.continues_parked.resize(after.passes.size());
  h.takes_result.resize(after.passes.size());
  h.clear_parked = options.start_over || !options.edited_shaders.empty();
  if (!running_from.plan || options.start_over || !running_from.plan->reuses_unchanged_passes || !after.reuses_unchanged_passes) return h;
  h.stale = stale_passes(running_from, options.edited_shaders);
  continue_running_results(running_from, h.clear_parked ? std::vector<ResultIdentity>{} : parked, after, h.stale, h);
  if (!results_from.plan || results_from.state->frame_index == 0) return h;
  const std::vector<bool> stale = results_from.plan == running_from.plan ? h.stale : stale_passes(results_from, options.edited_shaders);
  carry_results(results_from, after, stale, h);
  if (options.picture_may_stand && after.refines_apart) stand_picture(results_from, after, h);
  return h;
}

}  // namespace caustica::graph
