#pragma once
// The best evaluation's policy, kept in the run folder: best.srics, the acting networks of the
// policy version whose evaluation had the lowest average distance (arm and objects) so far, in
// the learner checkpoint's format (`srics eval RUN/best.srics` plays it), and best.yaml, which
// evaluation that was. Both are written durably (common/files: aside, fsynced, renamed). The
// passive policy's evaluations (version 0) never count.
//
// It sees the weights as they are published (it keeps the last few versions' parameters) and
// every evaluation; an evaluation of a version no longer kept cannot be copied and is logged.
// A resumed run reads best.yaml and only replaces the file with a better evaluation.
//
// Threading: one thread calls everything.

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/config/config.h"

namespace srics::launcher {

// Which evaluation best.srics holds (best.yaml).
struct BestEvaluation {
  uint64_t policy_version = 0;
  uint64_t update_count = 0;
  uint64_t env_steps = 0;
  double avg_distance = 0;
};

class BestPolicy {
 public:
  // Weights versions kept for evaluations still to come: as many as fit in this many bytes, and
  // at least kMinKeptVersions. An evaluation reports a version 5-60 versions old when the learner
  // publishes every 50 updates at 160 updates/s (the default run: with 4 kept, most of its best
  // evaluations could not be copied); a version is the policy's size (0.26 MB for the default
  // run's networks, up to ~5 MB for the paper's).
  static constexpr size_t kKeptBytes = size_t{64} << 20;
  static constexpr size_t kMinKeptVersions = 4;

  // `dir` is the run folder; the networks are built as an actor of `config` builds them.
  BestPolicy(const config::Config& config, std::string dir, size_t kept_bytes = kKeptBytes);
  ~BestPolicy();

  // Weights as published (every version, in order).
  void OnWeights(uint64_t version, uint64_t update_count, const std::string& architecture,
                 const std::vector<float>& parameters);
  // An evaluation. Returns what best.srics now holds when this evaluation replaced it, else
  // nothing. Throws std::runtime_error when the files cannot be written.
  std::optional<BestEvaluation> OnEval(uint64_t policy_version, uint64_t env_steps, double avg_distance);

  const std::optional<BestEvaluation>& best() const { return best_; }

 private:
  struct Kept {
    uint64_t version, update_count;
    std::vector<float> parameters;
  };
  struct Networks;
  std::string dir_;
  std::unique_ptr<Networks> networks_;
  std::deque<Kept> kept_;
  size_t kept_bytes_limit_;
  size_t kept_bytes_ = 0;
  std::optional<BestEvaluation> best_;
};

// best.yaml's text, and back (nothing when the text is not one).
std::string BestEvaluationYaml(const BestEvaluation& best);
std::optional<BestEvaluation> ParseBestEvaluation(const std::string& text);

}  // namespace srics::launcher
