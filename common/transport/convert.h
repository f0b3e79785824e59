#pragma once
// Internal: conversion between the domain type of each topic (common/rl) and the C type idlc
// generated from idl/srics.idl, once each way.

#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "common/rl/episode.h"
#include "common/transport/topics.h"
#include "common/transport/wire.h"
#include "srics.h"

namespace srics::transport::internal {

// What each type written on a topic is on the wire: the generated C type, its type descriptor
// and the topic.
template <typename C, const dds_topic_descriptor_t* kDescriptor, TopicId kTopicId>
struct Wire {
  using type = C;
  static constexpr TopicId kTopic = kTopicId;
  static const dds_topic_descriptor_t* Descriptor() { return kDescriptor; }
};
template <typename T>
struct CType;
template <>
struct CType<rl::Episode> : Wire<srics_Episode, &srics_Episode_desc, TopicId::kEpisode> {};
template <>
struct CType<rl::WeightsUpdate> : Wire<srics_PolicyWeights, &srics_PolicyWeights_desc, TopicId::kPolicyWeights> {};
template <>
struct CType<rl::GraphUpdate> : Wire<srics_InteractionGraph, &srics_InteractionGraph_desc, TopicId::kInteractionGraph> {
};
template <>
struct CType<rl::EvalReport> : Wire<srics_EvalResult, &srics_EvalResult_desc, TopicId::kEvalResult> {};
template <>
struct CType<rl::LearnerReport> : Wire<srics_LearnerStats, &srics_LearnerStats_desc, TopicId::kLearnerStats> {};
template <>
struct CType<rl::NodeStatus> : Wire<srics_NodeStatus, &srics_NodeStatus_desc, TopicId::kNodeStatus> {};

// X(T) for each domain type converted with an Envelope (rl::Episode apart: it needs limits).
#define SRICS_FOR_EACH_DOMAIN(X) \
  X(rl::LearnerReport) X(rl::EvalReport) X(rl::WeightsUpdate) X(rl::GraphUpdate) X(rl::NodeStatus)

// Where ToC puts the sequences whose domain element type is not the wire's (doubles sent as
// floats): the C sample points into it, so it must outlive the use of the sample. clear()
// keeps the vectors: a writer converting one message after another reuses their memory.
class SequenceBuffers {
 public:
  template <typename E>
  E* Hold(size_t n) {
    if constexpr (std::is_same_v<E, float>)
      return Next(floats_, used_floats_, n);
    else
      return Next(shorts_, used_shorts_, n);  // int16_t, the only other one
  }
  void clear() { used_floats_ = used_shorts_ = 0; }

 private:
  // one vector per sequence: a vector moved by the outer one keeps its buffer, so what an
  // earlier Hold returned stays valid
  template <typename E>
  static E* Next(std::vector<std::vector<E>>& pool, size_t& used, size_t n) {
    if (used == pool.size()) pool.emplace_back();
    std::vector<E>& buffer = pool[used++];
    buffer.resize(n);
    return buffer.data();
  }
  std::vector<std::vector<float>> floats_;
  std::vector<std::vector<int16_t>> shorts_;
  size_t used_floats_ = 0, used_shorts_ = 0;
};

// ToC fills *out with pointers into `in` (and `buffers`) where it can (no copy of sequences):
// they must outlive the use of *out, and *out must never be freed with the generated _free
// functions. Throws InvalidMessage for a string longer than its IDL bound. FromC copies
// everything once (a loaned sample goes back to DDS right after).

// The wire cannot say whether states carry velocities: `velocities` decides how entity_dim
// splits into identifier one-hot and xy(vxy). FromC takes any sample: rl::ValidateEpisode
// judges the result (a num_kinds below 1, a mode out of range).
void ToC(const rl::Episode& in, const Envelope& envelope, srics_Episode* out);
void FromC(const srics_Episode& in, bool velocities, rl::Episode* out);

// The other domain types: the envelope is the writer's, the rest the value's (floats rounded to
// the wire's). FromC takes any sample: Validate(value, envelope) judges the result.
void ToC(const rl::LearnerReport& in, const Envelope& envelope, srics_LearnerStats* out, SequenceBuffers* buffers);
void FromC(const srics_LearnerStats& in, rl::LearnerReport* out);
// selectivity goes out as 0 when no episode defined it, and comes in counted over every episode.
void ToC(const rl::EvalReport& in, const Envelope& envelope, srics_EvalResult* out, SequenceBuffers* buffers);
void FromC(const srics_EvalResult& in, rl::EvalReport* out);
// The parameters are borrowed, not copied; the checksum is left 0 (the writer stamps it) and
// not read (the reader checks it: Validate).
void ToC(const rl::WeightsUpdate& in, const Envelope& envelope, srics_PolicyWeights* out, SequenceBuffers* buffers);
void FromC(const srics_PolicyWeights& in, rl::WeightsUpdate* out);
// The structure goes out as its ancestor masks and depths and comes in as the sample has them
// (no partners), not yet checked against the adjacency (GraphFeed does: AdoptComputedStructure).
void ToC(const rl::GraphUpdate& in, const Envelope& envelope, srics_InteractionGraph* out, SequenceBuffers* buffers);
void FromC(const srics_InteractionGraph& in, rl::GraphUpdate* out);
// Strings beyond their IDL bound throw (StatusPublisher cuts the detail to it first).
void ToC(const rl::NodeStatus& in, const Envelope& envelope, srics_NodeStatus* out, SequenceBuffers* buffers);
void FromC(const srics_NodeStatus& in, rl::NodeStatus* out);

// The run id and the envelope of a received sample, read without copying the rest.
template <typename C>
std::string RunIdOf(const C& in) {
  return std::string(in.run_id, strnlen(in.run_id, sizeof in.run_id));
}
template <typename C>
Envelope EnvelopeOf(const C& in) {
  return {in.contract_version, RunIdOf(in)};
}

}  // namespace srics::transport::internal
