// An ETA from a run's recent pace, not from its average since the start. A run whose cost per unit
// of progress changes on the way read its cheap beginning as its future: a surrogate column, answered
// by the library while it stands, read "ETA 1 min 25 s" a third of the way in with some 4 min left
// (stop 74). The pace here is that of the last `window` seconds of wall time, so an ETA follows such
// a change within one window; before a window has passed it is the average since the first sample,
// as before. A cost that keeps rising still reads low, by less.
//
// Promises:
// - record(wall, progress) takes samples of a nondecreasing wall time [s] and of the progress made by
//   then, as a fraction of the whole (a resumed run's first sample is where it resumed).
// - eta() is (1 − progress) over the pace from the newest sample kept at least `window` seconds before
//   the last one (the first sample while none is that old) to the last one. It is NaN until two
//   samples span some wall time and some progress (duration_text reads NaN "unknown").
// - It keeps only the samples of the last window, and one before it.
#pragma once
#include <deque>
#include <limits>
#include <stdexcept>

namespace grainbank::common {

class RecentPaceEta {
 public:
  explicit RecentPaceEta(double window_seconds) : window_(window_seconds) {
    if (!(window_seconds > 0)) throw std::invalid_argument("RecentPaceEta: the window must be > 0 s");
  }

  void record(double wall_seconds, double progress) {
    samples_.push_back({wall_seconds, progress});
    // Drop the oldest while the next is old enough to span the window by itself.
    while (samples_.size() > 2 && samples_[1].wall <= wall_seconds - window_) samples_.pop_front();
  }

  double eta() const {
    if (samples_.size() < 2) return std::numeric_limits<double>::quiet_NaN();
    const Sample &from = samples_.front(), &to = samples_.back();
    if (!(to.wall > from.wall && to.progress > from.progress)) return std::numeric_limits<double>::quiet_NaN();
    return (1 - to.progress) * (to.wall - from.wall) / (to.progress - from.progress);
  }

 private:
  struct Sample {
    double wall, progress;
  };
  double window_;
  std::deque<Sample> samples_;
};

}  // namespace grainbank::common
