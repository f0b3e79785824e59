#pragma once
// Every random stream of a run derives from run.seed through this one function, so a run is
// reproducible from its config and no two streams share a seed by accident. Streams are
// named by purpose; `a` and `b` number the instances (actor id, episode id, ...).

#include <cstdint>

namespace srics::rl {

enum class SeedPurpose : uint64_t {
  kActorRng = 1,       // an actor's sampling stream: a = actor id, b = first episode id
  kEpisode = 2,        // an environment reset for a training/explore episode: a = actor, b = episode
  kEvalEpisode = 3,    // evaluation episode b: the same goals at every evaluation of a run
  kLearnerReplay = 4,  // replay sampling and relabeling
  kLearnerAgent = 5,   // network initialisation, action noise of the updates
  kGraphService = 6,   // data split, GNN initialisation, batches, Gumbel noise
};

// SplitMix64's finaliser: a bijective mix, so distinct inputs give distinct seeds.
inline uint64_t MixSeed(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

inline uint64_t DeriveSeed(uint64_t run_seed, SeedPurpose purpose, uint64_t a = 0, uint64_t b = 0) {
  return MixSeed(MixSeed(MixSeed(MixSeed(run_seed) ^ static_cast<uint64_t>(purpose)) ^ a) ^ b);
}

// Seed of evaluation episode i (the same for the policy and the passive baseline).
inline uint64_t EvalEpisodeSeed(uint64_t run_seed, int episode) {
  return DeriveSeed(run_seed, SeedPurpose::kEvalEpisode, 0, static_cast<uint64_t>(episode));
}

}  // namespace srics::rl
