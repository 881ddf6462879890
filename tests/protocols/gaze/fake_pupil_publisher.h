#pragma once
// A stand-in for Pupil Capture in tests: a REP socket ("Pupil Remote") on a free localhost port that
// answers "SUB_PORT" with the port of a PUB socket, on which the test publishes surface messages
// shaped like Pupil's ("surfaces.<name>" + msgpack map with "gaze_on_surfaces"), and "t" with its
// Pupil time: the process's steady clock in seconds plus pupil_minus_steady_s.
#include <atomic>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <zmq.hpp>

namespace fovlab::testing {

struct FakeSurfaceGaze {
  double x = 0.5;  // norm_pos, surface-normalised, origin bottom-left
  double y = 0.5;
  bool on_surf = true;
  double confidence = 1.0;
  double timestamp = 0.0;  // Pupil time
};

// msgpack payload of a surface message with these gaze entries.
std::string pack_surface_message(const std::string& surface, const std::vector<FakeSurfaceGaze>& gaze);

class FakePupilPublisher {
 public:
  // Binds both sockets on 127.0.0.1 (ephemeral ports) and starts answering. time_answer: what "t"
  // is answered with; empty: the Pupil time now.
  explicit FakePupilPublisher(double pupil_minus_steady_s = 0.0, std::string time_answer = {});
  ~FakePupilPublisher();
  FakePupilPublisher(const FakePupilPublisher&) = delete;
  FakePupilPublisher& operator=(const FakePupilPublisher&) = delete;

  int remote_port() const { return remote_port_; }
  int pub_port() const { return pub_port_; }
  int requests_answered() const { return requests_answered_.load(); }            // SUB_PORT requests
  int time_requests_answered() const { return time_requests_answered_.load(); }  // "t" requests
  double pupil_minus_steady_s() const { return pupil_minus_steady_s_; }
  // The fake's Pupil time for a moment of the steady clock (seconds since its epoch).
  double pupil_time_at(double steady_s) const { return steady_s + pupil_minus_steady_s_; }

  void publish(const std::string& topic, const std::string& payload);
  void publish_gaze(const std::string& surface, const std::vector<FakeSurfaceGaze>& gaze) {
    publish("surfaces." + surface, pack_surface_message(surface, gaze));
  }
  // Publishes (topic, payload) every few milliseconds until done() or timeout_s passes (ZeroMQ's
  // slow joiner: a new subscriber misses what was sent before it connected). Returns done().
  bool publish_until(const std::string& topic, const std::string& payload, const std::function<bool()>& done,
                     double timeout_s = 2.0);

 private:
  void answer_loop();

  zmq::context_t context_;
  zmq::socket_t remote_;     // REP, used by the answering thread only
  zmq::socket_t publisher_;  // PUB, used by the test's thread only
  double pupil_minus_steady_s_ = 0.0;
  std::string time_answer_;
  int remote_port_ = 0;
  int pub_port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> requests_answered_{0};
  std::atomic<int> time_requests_answered_{0};
  std::thread answerer_;
};

// The process's steady clock in seconds (the clock the fake's Pupil time runs on).
double steady_now_s();

// A localhost TCP port with nothing listening on it (bound, then released).
int unused_local_port();

}  // namespace fovlab::testing
