#include "common/transport/validation.h"

#include <cmath>
#include <cstring>

#include <libdeflate.h>

namespace srics::transport {
namespace {

Validation Malformed(std::string counter, std::string reason) {
  return {Verdict::kMalformed, std::move(reason), std::move(counter)};
}

// Index of the first non-finite value, or -1.
template <typename V>
int64_t FirstNonFinite(const std::vector<V>& values) {
  for (size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) return static_cast<int64_t>(i);
  return -1;
}

// Checks shared by every topic; returns a malformed verdict or an empty reason.
Validation CheckCommon(const char* topic, uint32_t contract_version, const std::string& msg_run_id) {
  const std::string counter = std::string(topic) + ".envelope";
  if (contract_version != kContractVersion)
    return Malformed(counter, "contract_version " + std::to_string(contract_version) + ", expected " +
                                  std::to_string(kContractVersion));
  if (msg_run_id.empty()) return Malformed(counter, "empty run_id");
  if (msg_run_id.size() > kRunIdMaxLength) return Malformed(counter, "run_id longer than 64 characters");
  return {};
}

Validation CheckRun(const std::string& msg_run_id, std::string_view run_id) {
  if (!run_id.empty() && msg_run_id != run_id)
    return {Verdict::kOtherRun, "run_id '" + msg_run_id + "' is not '" + std::string(run_id) + "'", ""};
  return {};
}

std::string SizeMismatch(const char* field, size_t got, uint64_t expected, const char* layout) {
  return std::string(field) + " has " + std::to_string(got) + " values, expected " + std::to_string(expected) + " (" +
         layout + ")";
}

// Reason for the first non-finite value of `field`, or "".
template <typename V>
std::string NonFinite(const char* field, const std::vector<V>& values) {
  const int64_t i = FirstNonFinite(values);
  if (i < 0) return "";
  return std::string(field) + "[" + std::to_string(i) + "] is not finite (" + std::to_string(values[i]) + ")";
}

// True when every bit of `mask` is below bit n.
bool MaskInside(uint64_t mask, uint32_t n) { return n >= 64 || (mask >> n) == 0; }

}  // namespace

Validation ValidateEnvelope(uint32_t contract_version, const std::string& msg_run_id, std::string_view run_id) {
  if (auto v = CheckCommon("episode", contract_version, msg_run_id); !v.ok()) return v;
  return CheckRun(msg_run_id, run_id);
}

Validation Validate(const rl::WeightsUpdate& msg, const Envelope& envelope, std::optional<uint32_t> checksum,
                    std::string_view run_id) {
  if (auto v = CheckCommon("weights", envelope.contract_version, envelope.run_id); !v.ok()) return v;
  if (msg.version < 1) return Malformed("weights.version", "version 0 (published weights start at 1)");
  if (msg.architecture.empty() || msg.architecture.size() > kArchitectureMaxLength)
    return Malformed("weights.architecture", "architecture empty or longer than 256 characters");
  if (msg.parameters.empty() || msg.parameters.size() > kMaxParameters)
    return Malformed("weights.size",
                     "parameters: " + std::to_string(msg.parameters.size()) + " values, expected 1 to 64 Mi");
  // one vectorized pass over the megabytes; the two named checks below only when it failed
  if (!rl::AllFiniteWithin(msg.parameters.data(), msg.parameters.size(), rl::kMaxAbsParameter)) {
    if (auto r = NonFinite("parameters", msg.parameters); !r.empty()) return Malformed("weights.nonfinite", r);
    // finite but huge parameters overflow the policy's activations into NaN actions
    for (size_t i = 0; i < msg.parameters.size(); ++i)
      if (std::fabs(msg.parameters[i]) > rl::kMaxAbsParameter)
        return Malformed("weights.magnitude", "parameters[" + std::to_string(i) +
                                                  "] = " + std::to_string(msg.parameters[i]) + " outside +-" +
                                                  std::to_string(rl::kMaxAbsParameter));
  }
  if (checksum)
    if (const uint32_t crc = ParameterChecksum(msg.parameters); crc != *checksum)
      return Malformed("weights.checksum", "checksum " + std::to_string(*checksum) +
                                               " does not match the parameters (" + std::to_string(crc) + ")");
  return CheckRun(envelope.run_id, run_id);
}

Validation Validate(const rl::GraphUpdate& update, const Envelope& envelope, std::string_view run_id) {
  if (auto v = CheckCommon("graph", envelope.contract_version, envelope.run_id); !v.ok()) return v;
  const rl::InteractionGraph& msg = update.graph;
  const std::vector<uint64_t>& ancestor_masks = update.structure.ancestor_mask;  // as received
  const std::vector<int>& depths = update.structure.depth;
  const uint32_t n = static_cast<uint32_t>(msg.num_entities);
  if (update.version < 1) return Malformed("graph.version", "version 0 (published graphs start at 1)");
  if (n < 1 || n > kMaxEntities)
    return Malformed("graph.size", "num_entities " + std::to_string(n) + " not in [1, 64]");
  if (update.mean_weights.size() != n * n)
    return Malformed("graph.size", SizeMismatch("mean_weights", update.mean_weights.size(), n * n, "N x N"));
  if (msg.adjacency.size() != n * n)
    return Malformed("graph.size", SizeMismatch("adjacency", msg.adjacency.size(), n * n, "N x N"));
  if (ancestor_masks.size() != n)
    return Malformed("graph.size", SizeMismatch("ancestor_masks", ancestor_masks.size(), n, "N"));
  if (depths.size() != n) return Malformed("graph.size", SizeMismatch("depths", depths.size(), n, "N"));
  if (msg.action_entity < 0 || msg.action_entity >= static_cast<int32_t>(n))
    return Malformed("graph.range", "action_entity " + std::to_string(msg.action_entity) + " not in [0, N)");
  for (size_t i = 0; i < msg.adjacency.size(); ++i)
    if (msg.adjacency[i] > 1)
      return Malformed("graph.range", "adjacency[" + std::to_string(i) + "] is neither 0 nor 1");
  for (uint32_t i = 0; i < n; ++i) {
    if (!MaskInside(ancestor_masks[i], n))
      return Malformed("graph.range", "ancestor_masks[" + std::to_string(i) + "] has bits at or above N");
    // a longest simple path from the action node has at most N edges
    if (depths[i] < -1 || depths[i] > static_cast<int32_t>(n))
      return Malformed("graph.range",
                       "depths[" + std::to_string(i) + "] = " + std::to_string(depths[i]) + " not in [-1, N]");
  }
  if (auto r = NonFinite("mean_weights", update.mean_weights); !r.empty()) return Malformed("graph.nonfinite", r);
  if (!std::isfinite(update.threshold)) return Malformed("graph.nonfinite", "threshold is not finite");
  if (!std::isfinite(update.held_out_loss)) return Malformed("graph.nonfinite", "held_out_loss is not finite");
  return CheckRun(envelope.run_id, run_id);
}

Validation Validate(const rl::EvalReport& report, const Envelope& envelope, std::string_view run_id) {
  if (auto v = CheckCommon("eval", envelope.contract_version, envelope.run_id); !v.ok()) return v;
  const rl::EvaluationSummary& msg = report.summary;
  const size_t n = msg.entity_distance.size();
  if (n < 1 || n > kMaxEntities)
    return Malformed("eval.size", "entity_distance has " + std::to_string(n) + " values, expected 1 to 64 (N)");
  if (msg.subgoal_success.size() != n)
    return Malformed("eval.size",
                     SizeMismatch("subgoal_success", msg.subgoal_success.size(), n, "N, as entity_distance"));
  for (double v : {msg.avg_distance, msg.avg_object_distance, msg.success_rate, msg.selectivity})
    if (!std::isfinite(v))
      return Malformed("eval.nonfinite", "a mean (distance, success rate or selectivity) is not finite");
  if (auto r = NonFinite("entity_distance", msg.entity_distance); !r.empty()) return Malformed("eval.nonfinite", r);
  if (auto r = NonFinite("subgoal_success", msg.subgoal_success); !r.empty()) return Malformed("eval.nonfinite", r);
  if (msg.success_rate < 0 || msg.success_rate > 1) return Malformed("eval.range", "success_rate outside [0, 1]");
  for (size_t i = 0; i < n; ++i)
    if (msg.subgoal_success[i] < 0 || msg.subgoal_success[i] > 1)
      return Malformed("eval.range", "subgoal_success[" + std::to_string(i) + "] outside [0, 1]");
  if (msg.avg_distance < 0 || msg.avg_object_distance < 0) return Malformed("eval.range", "a negative distance");
  if (msg.independent_undone > msg.independent_solved)
    return Malformed("eval.range", "independent_undone (" + std::to_string(msg.independent_undone) +
                                       ") exceeds independent_solved (" + std::to_string(msg.independent_solved) + ")");
  for (size_t i = 0; i < n; ++i)
    if (msg.entity_distance[i] < 0)
      return Malformed("eval.range", "entity_distance[" + std::to_string(i) + "] is negative");
  return CheckRun(envelope.run_id, run_id);
}

Validation Validate(const rl::LearnerReport&, const Envelope& envelope, std::string_view run_id) {
  // the float fields are reports for people: NaN or Inf (a diverged learner) is shown as is;
  // actors check the counters against their run (rl::ImplausibleProgress) before using them
  if (auto v = CheckCommon("stats", envelope.contract_version, envelope.run_id); !v.ok()) return v;
  return CheckRun(envelope.run_id, run_id);
}

Validation Validate(const rl::NodeStatus& msg, const Envelope& envelope, std::string_view run_id) {
  // strings are shown to people: monitors strip control characters (monitor/display.h)
  if (auto v = CheckCommon("status", envelope.contract_version, envelope.run_id); !v.ok()) return v;
  if (msg.role.empty() || msg.role.size() > kRoleMaxLength)
    return Malformed("status.size", "role empty or longer than 32");
  if (msg.host.size() > kHostMaxLength) return Malformed("status.size", "host longer than 128 characters");
  if (msg.report.detail.size() > kDetailMaxLength) return Malformed("status.size", "detail longer than 256 characters");
  const int32_t state = static_cast<int32_t>(msg.report.phase);
  if (state < 0 || state > 6)
    return Malformed("status.range", "state " + std::to_string(state) + " is not a NodeState");
  return CheckRun(envelope.run_id, run_id);
}

uint32_t ParameterChecksum(const std::vector<float>& parameters) {
  // zlib's CRC-32 (same polynomial and result); libdeflate's folds with carry-less multiplies,
  // 3x zlib 1.2's speed here: 5 MB weights are summed by the learner and by every actor
  return libdeflate_crc32(0, parameters.data(), parameters.size() * sizeof(float));
}

}  // namespace srics::transport
