#pragma once
// How a log's events make trials (docs/log-schema.md), shared by the full reader (session_record,
// for resume and replay) and the fast scan (session_scan, for analysis), which keep different
// things of each trial: a trial_start opens a trial; the events of a trial (is_trial_event) must
// name the open one; trial_end completes it; a session_resumed drops a trial left open (a crash cut
// it off, the resumed session runs it again); of two complete records of one index, the later one
// counts.
#include <algorithm>
#include <optional>
#include <vector>

namespace fovlab {

template <typename Trial>  // with an `int index`
class TrialAssembly {
 public:
  void start(Trial trial) { open_ = std::move(trial); }
  // The open trial when `trial` names it, else nullptr (an event outside its trial).
  Trial* open_for(std::optional<int> trial) { return open_ && trial && *trial == open_->index ? &*open_ : nullptr; }
  void end() {
    complete_.push_back(std::move(*open_));
    open_.reset();
  }
  void resume() { open_.reset(); }
  int incomplete_index() const { return open_ ? open_->index : -1; }

  // The complete trials by index, one per index.
  std::vector<Trial> take_complete() {
    std::stable_sort(complete_.begin(), complete_.end(), [](const Trial& a, const Trial& b) { return a.index < b.index; });
    std::vector<Trial> trials;
    for (size_t i = 0; i < complete_.size(); ++i)
      if (i + 1 == complete_.size() || complete_[i + 1].index != complete_[i].index) trials.push_back(std::move(complete_[i]));
    complete_.clear();
    return trials;
  }

 private:
  std::optional<Trial> open_;
  std::vector<Trial> complete_;  // in log order
};

}  // namespace fovlab
