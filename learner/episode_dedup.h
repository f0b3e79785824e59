#pragma once
// Which episodes the learner has already stored, so that none is ingested twice: a sample
// delivered again (a foreign participant replaying a captured episode, a writer's
// retransmission after a restart) is refused and counted instead of being trained on twice.
//
// An episode is (actor_id, episode_id); an actor's ids only increase (a restarted actor starts
// a new generation, process::NextActorFirstEpisodeId). Bounded memory whatever arrives: per
// actor the last `window` ids are kept, and an id at or below the highest one forgotten counts
// as seen; at most `max_actors` actors are tracked (the longest silent is forgotten first).
//
//   EpisodeDedup seen;
//   if (seen.Seen(e.actor_id, e.episode_id)) refuse(); else if (stored) seen.Remember(...);

#include <cstddef>
#include <cstdint>
#include <set>
#include <unordered_map>

namespace srics::learner {

class EpisodeDedup {
 public:
  explicit EpisodeDedup(size_t window = 1024, size_t max_actors = 256);

  // True when this episode was remembered before (or is older than the actor's window).
  bool Seen(uint32_t actor_id, uint64_t episode_id) const;
  // Records a stored episode.
  void Remember(uint32_t actor_id, uint64_t episode_id);

  size_t actors() const { return actors_.size(); }
  size_t ids() const;  // over all actors (bounded by window * max_actors)

 private:
  struct Actor {
    std::set<uint64_t> recent;
    bool forgot_any = false;
    uint64_t forgotten_up_to = 0;  // every id <= this counts as seen once forgot_any
    uint64_t last_use = 0;
  };
  size_t window_;
  size_t max_actors_;
  uint64_t clock_ = 0;
  std::unordered_map<uint32_t, Actor> actors_;
};

}  // namespace srics::learner
