#pragma once
// How a log's events make trials (docs/log-schema.md), shared by the full reader (session_record,
// for resume and replay) and the fast scan (session_scan, for analysis), which keep different
// things of each trial: a trial_start opens a trial; the events of a trial (is_trial_event) must
// name the open one; trial_end completes it; a session_resumed drops a trial left open (a crash cut
// it off, the resumed session runs it again). A trial index completes once: a resumed session
// starts after the last complete trial, so a second record of one index means the log was forged
// or spliced, and end() says so.
#include <algorithm>
#include <optional>
#include <unordered_set>
#include <vector>

namespace fovlab {

template <typename Trial>  // with an `int index`
class TrialAssembly {
 public:
  void start(Trial trial) { open_ = std::move(trial); }
  // The open trial when `trial` names it, else nullptr (an event outside its trial).
  Trial* open_for(std::optional<int> trial) { return open_ && trial && *trial == open_->index ? &*open_ : nullptr; }
  // Completes the open trial; false when its index already completed earlier in the log.
  bool end() {
    const bool first = completed_indices_.insert(open_->index).second;
    complete_.push_back(std::move(*open_));
    open_.reset();
    return first;
  }
  int complete_count() const { return static_cast<int>(complete_.size()); }
  void resume() { open_.reset(); }
  int incomplete_index() const { return open_ ? open_->index : -1; }

  // The complete trials by index.
  std::vector<Trial> take_complete() {
    std::stable_sort(complete_.begin(), complete_.end(),
                     [](const Trial& a, const Trial& b) { return a.index < b.index; });
    return std::move(complete_);
  }

 private:
  std::optional<Trial> open_;
  std::vector<Trial> complete_;  // in log order
  std::unordered_set<int> completed_indices_;
};

}  // namespace fovlab
