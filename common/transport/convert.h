#pragma once
// Internal: conversion between the plain structs of messages.h and the C types idlc
// generated from idl/srics.idl.

#include "common/transport/messages.h"
#include "srics.h"

namespace srics::transport::internal {

// The generated C type and type descriptor of each message struct.
template <typename T> struct CType;
template <> struct CType<Episode> { using type = srics_Episode; static const dds_topic_descriptor_t* Descriptor() { return &srics_Episode_desc; } };
template <> struct CType<PolicyWeights> { using type = srics_PolicyWeights; static const dds_topic_descriptor_t* Descriptor() { return &srics_PolicyWeights_desc; } };
template <> struct CType<InteractionGraph> { using type = srics_InteractionGraph; static const dds_topic_descriptor_t* Descriptor() { return &srics_InteractionGraph_desc; } };
template <> struct CType<EvalResult> { using type = srics_EvalResult; static const dds_topic_descriptor_t* Descriptor() { return &srics_EvalResult_desc; } };
template <> struct CType<LearnerStats> { using type = srics_LearnerStats; static const dds_topic_descriptor_t* Descriptor() { return &srics_LearnerStats_desc; } };
template <> struct CType<NodeStatus> { using type = srics_NodeStatus; static const dds_topic_descriptor_t* Descriptor() { return &srics_NodeStatus_desc; } };

// ToC fills *out with pointers into `in` (no copy of sequences): `in` must outlive the use of
// *out, and *out must never be freed with the generated _free functions. Throws
// InvalidMessage for a string longer than its IDL bound.
// FromC copies everything (a loaned sample goes back to DDS right after).
void ToC(const Episode& in, srics_Episode* out);
void ToC(const PolicyWeights& in, srics_PolicyWeights* out);
void ToC(const InteractionGraph& in, srics_InteractionGraph* out);
void ToC(const EvalResult& in, srics_EvalResult* out);
void ToC(const LearnerStats& in, srics_LearnerStats* out);
void ToC(const NodeStatus& in, srics_NodeStatus* out);

void FromC(const srics_Episode& in, Episode* out);
void FromC(const srics_PolicyWeights& in, PolicyWeights* out);
void FromC(const srics_InteractionGraph& in, InteractionGraph* out);
void FromC(const srics_EvalResult& in, EvalResult* out);
void FromC(const srics_LearnerStats& in, LearnerStats* out);
void FromC(const srics_NodeStatus& in, NodeStatus* out);

}  // namespace srics::transport::internal
