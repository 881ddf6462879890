#include "protocols/session/response_source.h"

namespace fovlab {

std::optional<Answer> KeyResponses::await(const AnswerRequest& request, Presenter& presenter, double timeout_s) {
  presenter.poll_input();  // presses before the question appeared do not count
  const double period_s = 1.0 / presenter.refresh_hz();
  for (;;) {
    if (presenter.close_requested()) throw SessionAborted{presenter.close_reason()};
    for (const InputEvent& input : presenter.poll_input())
      for (const auto& [answer, keys] : question_.answers)
        for (const std::string& key : keys)
          if (key == input.key) return Answer{request.trial ? answer : std::string(), input.key, input.time_s};
    if (timeout_s > 0 && presenter.now_s() - request.onset_s >= timeout_s) return std::nullopt;
    presenter.wait_until(presenter.now_s() + period_s);
  }
}

std::optional<Answer> ObserverResponses::await(const AnswerRequest& request, Presenter& presenter, double timeout_s) {
  if (presenter.close_requested()) throw SessionAborted{presenter.close_reason()};
  ObserverAnswer decided;
  if (!request.trial) {
    decided.response_time_s = observer_.instructions_time_s();
  } else {
    const Trial& trial = *request.trial;
    const ProtocolKind kind = observer_.plan().config.protocol.kind;
    if (kind == ProtocolKind::ramp) decided = observer_.answer_ramp_step(trial, request.step);
    else if (kind == ProtocolKind::slider) decided = observer_.answer_slider(trial, request.step, request.ladder_index);
    else decided = observer_.answer_comparison(trial);
  }
  if (timeout_s > 0 && decided.response_time_s > timeout_s) {
    presenter.wait_until(request.onset_s + timeout_s);
    return std::nullopt;
  }
  presenter.wait_until(request.onset_s + decided.response_time_s);
  return Answer{decided.answer, "simulated", presenter.now_s()};
}

}  // namespace fovlab
