#pragma once
// Where answers come from: the participant's keys and gamepad buttons (through the presenter), or
// a simulated observer. The session asks for one answer at a time.
#include <optional>
#include <string>
#include <vector>

#include "study/config/study_config.h"
#include "protocols/observer/simulated_observer.h"
#include "display/presenter.h"

namespace fovlab {

struct AnswerRequest {
  const Trial* trial = nullptr;  // nullptr for the instructions screen
  int step = 0;                  // ramp: the sequence step answered; slider: the action number
  int ladder_index = 0;          // slider: where the ladder stands
  double onset_s = 0.0;          // presenter time the question appeared
};

struct Answer {
  std::string answer;   // one of the protocol's answers ("" for the instructions)
  std::string key;      // the key or button, or "simulated"
  double time_s = 0.0;  // presenter time of the answer
};

class ResponseSource {
 public:
  virtual ~ResponseSource() = default;
  // Waits for an answer; nullopt when timeout_s (> 0) passes first.
  virtual std::optional<Answer> await(const AnswerRequest& request, Presenter& presenter, double timeout_s) = 0;
  virtual std::string describe() const = 0;  // "keyboard" or "simulated:..."
};

// Keys and buttons mapped by the config's [protocol.keys]; any of them starts the session.
class KeyResponses final : public ResponseSource {
 public:
  explicit KeyResponses(const QuestionConfig& question) : question_(question) {}
  std::optional<Answer> await(const AnswerRequest& request, Presenter& presenter, double timeout_s) override;
  std::string describe() const override { return "keyboard"; }

 private:
  const QuestionConfig& question_;
};

class ObserverResponses final : public ResponseSource {
 public:
  ObserverResponses(ObserverModel model, const StudyPlan& plan) : observer_(model, plan) {}
  std::optional<Answer> await(const AnswerRequest& request, Presenter& presenter, double timeout_s) override;
  std::string describe() const override { return "simulated"; }
  const SimulatedObserver& observer() const { return observer_; }

 private:
  SimulatedObserver observer_;
};

// The participant closed the window or pressed Escape three times: the session stops where it is
// (the log holds everything up to the last complete trial; `fovlab run` again resumes).
struct SessionAborted {
  std::string reason;
};

}  // namespace fovlab
