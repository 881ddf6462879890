#include "tests/protocols/gaze/fake_pupil_publisher.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <msgpack.hpp>

namespace fovlab::testing {

namespace {

int bound_port(zmq::socket_t& socket) {
  const std::string endpoint = socket.get(zmq::sockopt::last_endpoint);  // "tcp://127.0.0.1:PORT"
  return std::stoi(endpoint.substr(endpoint.rfind(':') + 1));
}

}  // namespace

std::string pack_surface_message(const std::string& surface, const std::vector<FakeSurfaceGaze>& gaze) {
  msgpack::sbuffer buffer;
  msgpack::packer<msgpack::sbuffer> packer(buffer);
  packer.pack_map(4);
  packer.pack(std::string("topic"));
  packer.pack("surfaces." + surface);
  packer.pack(std::string("name"));
  packer.pack(surface);
  packer.pack(std::string("gaze_on_surfaces"));
  packer.pack_array(static_cast<uint32_t>(gaze.size()));
  for (const FakeSurfaceGaze& entry : gaze) {
    packer.pack_map(5);
    packer.pack(std::string("topic"));
    packer.pack("gaze.3d.01._on_surface");
    packer.pack(std::string("norm_pos"));
    packer.pack_array(2);
    packer.pack_double(entry.x);
    packer.pack_double(entry.y);
    packer.pack(std::string("confidence"));
    packer.pack_double(entry.confidence);
    packer.pack(std::string("on_surf"));
    packer.pack(entry.on_surf);
    packer.pack(std::string("timestamp"));
    packer.pack_double(entry.timestamp);
  }
  packer.pack(std::string("timestamp"));
  packer.pack_double(gaze.empty() ? 0.0 : gaze.back().timestamp);
  return std::string(buffer.data(), buffer.size());
}

double steady_now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

FakePupilPublisher::FakePupilPublisher(double pupil_minus_steady_s, std::string time_answer)
    : remote_(context_, zmq::socket_type::rep),
      publisher_(context_, zmq::socket_type::pub),
      pupil_minus_steady_s_(pupil_minus_steady_s),
      time_answer_(std::move(time_answer)) {
  remote_.set(zmq::sockopt::linger, 0);
  remote_.set(zmq::sockopt::rcvtimeo, 10);
  remote_.bind("tcp://127.0.0.1:*");
  remote_port_ = bound_port(remote_);
  publisher_.set(zmq::sockopt::linger, 0);
  publisher_.bind("tcp://127.0.0.1:*");
  pub_port_ = bound_port(publisher_);
  answerer_ = std::thread([this] { answer_loop(); });
}

FakePupilPublisher::~FakePupilPublisher() {
  stop_.store(true);
  answerer_.join();
  remote_.close();
  publisher_.close();
}

void FakePupilPublisher::answer_loop() {
  while (!stop_.load()) {
    zmq::message_t request;
    if (!remote_.recv(request, zmq::recv_flags::none)) continue;
    std::string answer = "unknown command";
    if (request.to_string() == "SUB_PORT") {
      answer = std::to_string(pub_port_);
    } else if (request.to_string() == "t") {
      char text[64];  // Pupil answers with the time as a decimal number
      std::snprintf(text, sizeof text, "%.9f", pupil_time_at(steady_now_s()));
      answer = time_answer_.empty() ? std::string(text) : time_answer_;
    }
    // Counted before the reply goes out: a test that reads the count once its request was
    // answered must see it (counting after the send raced with the reader).
    if (request.to_string() == "t") time_requests_answered_.fetch_add(1);
    else requests_answered_.fetch_add(1);
    remote_.send(zmq::buffer(answer), zmq::send_flags::none);
  }
}

void FakePupilPublisher::publish(const std::string& topic, const std::string& payload) {
  publisher_.send(zmq::buffer(topic), zmq::send_flags::sndmore);
  publisher_.send(zmq::buffer(payload), zmq::send_flags::none);
}

bool FakePupilPublisher::publish_until(const std::string& topic, const std::string& payload,
                                       const std::function<bool()>& done, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    publish(topic, payload);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

int unused_local_port() {
  zmq::context_t context;
  zmq::socket_t socket(context, zmq::socket_type::rep);
  socket.set(zmq::sockopt::linger, 0);
  socket.bind("tcp://127.0.0.1:*");
  const int port = bound_port(socket);
  socket.close();
  return port;
}

}  // namespace fovlab::testing
