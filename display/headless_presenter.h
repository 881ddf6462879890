#pragma once
// Presentation without a window, on a virtual clock: every present advances the clock by exactly
// one refresh period, waits jump the clock forward, and there is no input (answers come from a
// simulated observer). Sessions run as fast as their stimuli can be fetched, and their times are
// reproducible.
#include <cmath>
#include <optional>

#include "core/test_pause.h"
#include "display/presenter.h"

namespace fovlab {

class HeadlessPresenter final : public Presenter {
 public:
  explicit HeadlessPresenter(double refresh_hz, double start_s = 0.0) : refresh_hz_(refresh_hz), now_s_(start_s) {}

  double now_s() override { return now_s_; }
  double present(const Rgba8Frame&) override { return next_refresh(); }
  double present(const DeviceRgba8Frame&) override { return next_refresh(); }
  std::vector<InputEvent> poll_input() override { return {}; }
  void wait_until(double time_s) override {
    // Whole refreshes, as a real display would show: the next vsync at or after time_s.
    if (time_s > now_s_) now_s_ += std::ceil((time_s - now_s_) * refresh_hz_ - 1e-9) / refresh_hz_;
  }
  std::optional<std::pair<double, double>> cursor_px() override { return std::nullopt; }
  // Never, unless a test set FOVLAB_TEST_CLOSE_AT_S (core/test_pause.h).
  bool close_requested() override { return close_at_s_ && now_s_ >= *close_at_s_; }
  double refresh_hz() const override { return refresh_hz_; }
  bool is_headless() const override { return true; }
  std::string present_clock() const override { return "virtual"; }

 private:
  double next_refresh() {
    now_s_ += 1.0 / refresh_hz_;
    return now_s_;
  }
  double refresh_hz_;
  double now_s_;
  std::optional<double> close_at_s_ = test_close_at_s();
};

}  // namespace fovlab
