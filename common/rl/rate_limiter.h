#pragma once
// Keeps updates per inserted transition near a target ratio, as Reverb's SampleToInsertRatio
// limiter does: no updates before `warmup` transitions, then the learner may run at most
// `error_buffer` updates ahead of ratio * (inserted - warmup), and inserters must wait when
// they are more than `error_buffer` updates ahead of the learner.

#include <algorithm>
#include <cstdint>

namespace srics::rl {

class RateLimiter {
 public:
  RateLimiter(double updates_per_insert, uint64_t warmup, double error_buffer)
      : ratio_(updates_per_insert), warmup_(warmup), buffer_(error_buffer) {}

  // Updates the data inserted so far pays for (before the error buffer).
  double Target(uint64_t inserted) const {
    return inserted < warmup_ ? 0.0 : ratio_ * static_cast<double>(inserted - warmup_);
  }
  // True when one more update keeps the learner within the buffer.
  bool CanUpdate(uint64_t inserted, uint64_t updates) const {
    return inserted >= warmup_ && ratio_ > 0 && static_cast<double>(updates + 1) <= Target(inserted) + buffer_;
  }
  // Updates the learner may do now without waiting for data.
  uint64_t UpdatesAllowed(uint64_t inserted, uint64_t updates) const {
    if (inserted < warmup_ || ratio_ <= 0) return 0;
    const double room = Target(inserted) + buffer_ - static_cast<double>(updates);
    return room < 1 ? 0 : static_cast<uint64_t>(room);
  }
  // True when `more` further transitions may be inserted without running more than the
  // buffer ahead of the learner. Warm-up data is always welcome.
  bool CanInsert(uint64_t inserted, uint64_t updates, uint64_t more) const {
    if (inserted + more <= warmup_ || ratio_ <= 0) return true;
    return Target(inserted + more) - static_cast<double>(updates) <= buffer_ + ratio_ * more;
  }

  double ratio() const { return ratio_; }
  uint64_t warmup() const { return warmup_; }

 private:
  double ratio_;
  uint64_t warmup_;
  double buffer_;
};

}  // namespace srics::rl
