#pragma once
// Internal: conversion between the plain structs of messages.h (and rl::Episode) and the C
// types idlc generated from idl/srics.idl.

#include <string>

#include "common/rl/episode.h"
#include "common/transport/messages.h"
#include "srics.h"

namespace srics::transport::internal {

// The generated C type and type descriptor of each message struct.
template <typename T>
struct CType;
template <>
struct CType<rl::Episode> {
  using type = srics_Episode;
  static const dds_topic_descriptor_t* Descriptor() { return &srics_Episode_desc; }
};
template <>
struct CType<PolicyWeights> {
  using type = srics_PolicyWeights;
  static const dds_topic_descriptor_t* Descriptor() { return &srics_PolicyWeights_desc; }
};
template <>
struct CType<InteractionGraph> {
  using type = srics_InteractionGraph;
  static const dds_topic_descriptor_t* Descriptor() { return &srics_InteractionGraph_desc; }
};
template <>
struct CType<EvalResult> {
  using type = srics_EvalResult;
  static const dds_topic_descriptor_t* Descriptor() { return &srics_EvalResult_desc; }
};
template <>
struct CType<LearnerStats> {
  using type = srics_LearnerStats;
  static const dds_topic_descriptor_t* Descriptor() { return &srics_LearnerStats_desc; }
};
template <>
struct CType<NodeStatus> {
  using type = srics_NodeStatus;
  static const dds_topic_descriptor_t* Descriptor() { return &srics_NodeStatus_desc; }
};

// X(T) for each message struct of messages.h (rl::Episode apart).
#define SRICS_FOR_EACH_MESSAGE(X) X(PolicyWeights) X(InteractionGraph) X(EvalResult) X(LearnerStats) X(NodeStatus)

// What an episode sample carries besides the rl::Episode: the writer supplies it.
struct Envelope {
  uint32_t contract_version = kContractVersion;
  std::string run_id;
};

// ToC fills *out with pointers into `in` (no copy of sequences): `in` must outlive the use of
// *out, and *out must never be freed with the generated _free functions. Throws
// InvalidMessage for a string longer than its IDL bound.
// FromC copies everything once (a loaned sample goes back to DDS right after).
template <typename T>
void ToC(const T& in, typename CType<T>::type* out);
template <typename T>
void FromC(const typename CType<T>::type& in, T* out);

// The wire cannot say whether states carry velocities: `velocities` decides how entity_dim
// splits into identifier one-hot and xy(vxy). FromC takes any sample: rl::ValidateEpisode
// judges the result (a num_kinds below 1, a mode out of range).
void ToC(const rl::Episode& in, const Envelope& envelope, srics_Episode* out);
void FromC(const srics_Episode& in, bool velocities, rl::Episode* out);
// The run id of a received episode, read without copying the rest.
std::string RunIdOf(const srics_Episode& in);

}  // namespace srics::transport::internal
