#include "protocols/gaze/pupil_gaze_source.h"

#include "core/number_text.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include <msgpack.hpp>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "core/input_error.h"

namespace fovlab {

namespace {

constexpr int receive_poll_ms = 20;  // how often the receiver thread looks at its stop flag

double steady_seconds(std::chrono::steady_clock::time_point time) {
  return std::chrono::duration<double>(time.time_since_epoch()).count();
}

bool is_key(const msgpack::object& key, std::string_view name) {
  if (key.type == msgpack::type::STR) return std::string_view(key.via.str.ptr, key.via.str.size) == name;
  if (key.type == msgpack::type::BIN) return std::string_view(key.via.bin.ptr, key.via.bin.size) == name;
  return false;
}

const msgpack::object* find(const msgpack::object& map, std::string_view name) {
  if (map.type != msgpack::type::MAP) return nullptr;
  for (uint32_t i = 0; i < map.via.map.size; ++i) {
    if (is_key(map.via.map.ptr[i].key, name)) return &map.via.map.ptr[i].val;
  }
  return nullptr;
}

std::optional<double> number(const msgpack::object* object) {
  if (object == nullptr) return std::nullopt;
  switch (object->type) {
    case msgpack::type::POSITIVE_INTEGER:
      return static_cast<double>(object->via.u64);
    case msgpack::type::NEGATIVE_INTEGER:
      return static_cast<double>(object->via.i64);
    case msgpack::type::FLOAT32:
    case msgpack::type::FLOAT64:
      return object->via.f64;
    default:
      return std::nullopt;
  }
}

}  // namespace

std::optional<GazeSample> decode_pupil_surface_gaze(std::string_view payload, double min_confidence, int width_px,
                                                    int height_px) {
  msgpack::object_handle handle;
  try {
    handle = msgpack::unpack(payload.data(), payload.size());
  } catch (const msgpack::unpack_error& error) {
    throw std::runtime_error(std::string("surface message is not msgpack: ") + error.what());
  }
  const msgpack::object& root = handle.get();
  if (root.type != msgpack::type::MAP) throw std::runtime_error("surface message is not a msgpack map");
  const msgpack::object* gaze = find(root, "gaze_on_surfaces");
  if (gaze == nullptr || gaze->type != msgpack::type::ARRAY) {
    throw std::runtime_error("surface message has no gaze_on_surfaces array");
  }

  // The entry with the latest timestamp (the last one of equal timestamps).
  const msgpack::object* chosen = nullptr;
  double chosen_time = -std::numeric_limits<double>::infinity();
  for (uint32_t i = 0; i < gaze->via.array.size; ++i) {
    const msgpack::object& entry = gaze->via.array.ptr[i];
    if (entry.type != msgpack::type::MAP) throw std::runtime_error("gaze_on_surfaces entry is not a map");
    const double time = number(find(entry, "timestamp")).value_or(-std::numeric_limits<double>::infinity());
    if (chosen == nullptr || time >= chosen_time) {
      chosen = &entry;
      chosen_time = time;
    }
  }
  if (chosen == nullptr) return std::nullopt;

  const msgpack::object* norm_pos = find(*chosen, "norm_pos");
  if (norm_pos == nullptr || norm_pos->type != msgpack::type::ARRAY || norm_pos->via.array.size != 2) {
    throw std::runtime_error("gaze_on_surfaces entry has no norm_pos [x, y]");
  }
  const std::optional<double> x = number(&norm_pos->via.array.ptr[0]);
  const std::optional<double> y = number(&norm_pos->via.array.ptr[1]);
  if (!x || !y) throw std::runtime_error("gaze_on_surfaces norm_pos is not two numbers");
  const double confidence = number(find(*chosen, "confidence")).value_or(1.0);
  const msgpack::object* on_surf = find(*chosen, "on_surf");
  const bool on_surface = on_surf == nullptr || on_surf->type != msgpack::type::BOOLEAN || on_surf->via.boolean;

  GazeSample sample;
  if (std::isfinite(chosen_time)) sample.acquired_s = chosen_time;  // Pupil time; the source maps it
  sample.x_px = *x * width_px;
  sample.y_px = (1.0 - *y) * height_px;
  if (!std::isfinite(sample.x_px) || !std::isfinite(sample.y_px)) {
    sample.x_px = sample.y_px = 0.0;
    sample.valid = false;
    sample.invalid_reason = "not_finite";
  } else if (!(confidence >= min_confidence)) {
    sample.valid = false;
    sample.invalid_reason = "low_confidence";
  } else if (!on_surface) {
    sample.valid = false;
    sample.invalid_reason = "off_screen";
  }
  return sample;
}

struct PupilGazeSource::Impl {
  PupilGazeOptions options;
  int width_px = 0;
  int height_px = 0;
  std::string name;   // "pupil:HOST:PORT"
  std::string topic;  // "surfaces.<surface>"

  zmq::context_t context;
  zmq::socket_t subscriber;  // used by the receiver thread only, once it runs
  std::thread receiver;
  std::atomic<bool> stop{false};
  std::atomic<uint64_t> received{0};
  std::atomic<uint64_t> malformed{0};

  // Set before the receiver starts, read-only afterwards.
  double clock_offset_s = 0.0;  // Pupil time - session time
  double clock_sync_rtt_s = 0.0;
  double steady_to_session_s = 0.0;  // session time - steady clock seconds, at the sync

  std::mutex mutex;  // guards the three below
  bool have_sample = false;
  GazeSample latest;  // acquired_s already on the session clock
  std::chrono::steady_clock::time_point latest_arrival;

  void receive_loop() {
    while (!stop.load(std::memory_order_relaxed)) {
      std::vector<zmq::message_t> parts;
      zmq::recv_result_t result;
      try {
        result = zmq::recv_multipart(subscriber, std::back_inserter(parts));
      } catch (const zmq::error_t& error) {
        if (error.num() == ETERM) return;
        continue;  // EINTR and the like: try again
      }
      if (!result) continue;  // receive timeout: look at the stop flag
      const auto arrival = std::chrono::steady_clock::now();
      // The subscription is a prefix ("surfaces.screen" also matches "surfaces.screen2").
      if (parts.size() < 2 || parts[0].to_string_view() != topic) continue;
      try {
        const std::optional<GazeSample> sample =
            decode_pupil_surface_gaze(parts[1].to_string_view(), options.min_confidence, width_px, height_px);
        if (!sample) continue;  // no gaze on this world frame
        GazeSample mapped = *sample;
        mapped.acquired_s =
            sample->acquired_s ? *sample->acquired_s - clock_offset_s : steady_seconds(arrival) + steady_to_session_s;
        {
          const std::lock_guard lock(mutex);
          latest = mapped;
          latest_arrival = arrival;
          have_sample = true;
        }
        received.fetch_add(1);
      } catch (const std::exception&) {
        malformed.fetch_add(1);
      }
    }
  }
};

PupilGazeSource::PupilGazeSource(PupilGazeOptions options, int width_px, int height_px)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.name = "pupil:" + options.host + ":" + std::to_string(options.port);
  if (options.surface != PupilGazeOptions{}.surface) impl.name += ",surface=" + options.surface;
  if (options.min_confidence != PupilGazeOptions{}.min_confidence)
    impl.name += ",min_confidence=" + format_number(options.min_confidence, 6);
  const auto fail = [&](const std::string& what) { throw InputError(impl.name + ": " + what); };
  if (options.host.empty()) fail("the host is empty");
  if (options.port < 1 || options.port > 65535) fail("port: expected 1..65535");
  if (options.surface.empty()) fail("surface: expected a surface name, got an empty one");
  if (!(options.min_confidence >= 0.0 && options.min_confidence <= 1.0)) {
    fail("min_confidence: expected 0..1, got " + exact_number_text(options.min_confidence));
  }
  if (!(options.staleness_s > 0.0) || !std::isfinite(options.staleness_s)) {
    fail("staleness_s: expected a positive number of seconds, got " + exact_number_text(options.staleness_s));
  }
  if (!(options.timeout_s > 0.0 && options.timeout_s <= 3600.0)) {
    fail("timeout_s: expected 0 < seconds <= 3600, got " + exact_number_text(options.timeout_s));
  }
  if (width_px <= 0 || height_px <= 0) {
    fail("screen size must be positive, got " + std::to_string(width_px) + "x" + std::to_string(height_px));
  }
  impl.options = std::move(options);
  impl.width_px = width_px;
  impl.height_px = height_px;
  impl.topic = "surfaces." + impl.options.surface;

  const int timeout_ms = std::max(1, static_cast<int>(std::lround(impl.options.timeout_s * 1000.0)));
  const std::string no_answer = "no answer from Pupil Remote within " + exact_number_text(impl.options.timeout_s) +
                                " s (is Pupil Capture running with the Network API plugin?)";
  const auto session_now = [&impl] {
    return impl.options.session_clock ? impl.options.session_clock() : steady_seconds(std::chrono::steady_clock::now());
  };
  std::string sub_port_text, pupil_time_text;
  double session_midpoint_s = 0.0;
  try {
    zmq::socket_t remote(impl.context, zmq::socket_type::req);
    remote.set(zmq::sockopt::linger, 0);
    remote.set(zmq::sockopt::sndtimeo, timeout_ms);
    remote.set(zmq::sockopt::rcvtimeo, timeout_ms);
    remote.connect("tcp://" + impl.options.host + ":" + std::to_string(impl.options.port));
    if (!remote.send(zmq::str_buffer("SUB_PORT"), zmq::send_flags::none)) fail(no_answer);
    zmq::message_t reply;
    if (!remote.recv(reply, zmq::recv_flags::none)) fail(no_answer);
    sub_port_text = reply.to_string();
    // Pupil time against the session clock, read on both sides of the request.
    const double before_s = session_now();
    const double steady_before_s = steady_seconds(std::chrono::steady_clock::now());
    if (!remote.send(zmq::str_buffer("t"), zmq::send_flags::none)) fail(no_answer);
    if (!remote.recv(reply, zmq::recv_flags::none)) fail(no_answer);
    const double after_s = session_now();
    const double steady_after_s = steady_seconds(std::chrono::steady_clock::now());
    pupil_time_text = reply.to_string();
    session_midpoint_s = 0.5 * (before_s + after_s);
    impl.clock_sync_rtt_s = after_s - before_s;
    impl.steady_to_session_s = session_midpoint_s - 0.5 * (steady_before_s + steady_after_s);
  } catch (const zmq::error_t& error) {
    fail(std::string("cannot talk to Pupil Remote (") + error.what() + ")");
  }

  int sub_port = 0;
  const auto [end, error] =
      std::from_chars(sub_port_text.data(), sub_port_text.data() + sub_port_text.size(), sub_port);
  if (error != std::errc() || end != sub_port_text.data() + sub_port_text.size() || sub_port < 1 || sub_port > 65535) {
    fail("Pupil Remote answered SUB_PORT with \"" + sub_port_text + "\", expected a port number");
  }

  double pupil_time_s = 0.0;
  const auto [time_end, time_error] =
      std::from_chars(pupil_time_text.data(), pupil_time_text.data() + pupil_time_text.size(), pupil_time_s);
  if (time_error != std::errc() || time_end != pupil_time_text.data() + pupil_time_text.size() ||
      !std::isfinite(pupil_time_s)) {
    fail("Pupil Remote answered t with \"" + pupil_time_text.substr(0, 40) + "\", expected Pupil time in seconds");
  }
  impl.clock_offset_s = pupil_time_s - session_midpoint_s;

  try {
    impl.subscriber = zmq::socket_t(impl.context, zmq::socket_type::sub);
    impl.subscriber.set(zmq::sockopt::linger, 0);
    impl.subscriber.set(zmq::sockopt::rcvtimeo, receive_poll_ms);
    impl.subscriber.set(zmq::sockopt::subscribe, impl.topic);
    impl.subscriber.connect("tcp://" + impl.options.host + ":" + std::to_string(sub_port));
  } catch (const zmq::error_t& zmq_error) {
    fail("cannot subscribe to port " + std::to_string(sub_port) + " (" + zmq_error.what() + ")");
  }
  impl.receiver = std::thread([&impl] { impl.receive_loop(); });
}

PupilGazeSource::~PupilGazeSource() {
  impl_->stop.store(true);
  if (impl_->receiver.joinable()) impl_->receiver.join();
  impl_->subscriber.close();
  impl_->context.close();
}

GazeSample PupilGazeSource::sample(double time_s) {
  const auto now = std::chrono::steady_clock::now();
  GazeSample result;
  {
    const std::lock_guard lock(impl_->mutex);
    const std::chrono::duration<double> age = now - impl_->latest_arrival;
    if (impl_->have_sample && age.count() <= impl_->options.staleness_s) {
      result = impl_->latest;
    } else {
      result.valid = false;
      result.invalid_reason = "no_data";
    }
  }
  result.time_s = time_s;
  return result;
}

std::string PupilGazeSource::describe() const { return impl_->name; }

uint64_t PupilGazeSource::messages_received() const { return impl_->received.load(); }
double PupilGazeSource::clock_offset_s() const { return impl_->clock_offset_s; }
double PupilGazeSource::clock_sync_rtt_s() const { return impl_->clock_sync_rtt_s; }
uint64_t PupilGazeSource::messages_malformed() const { return impl_->malformed.load(); }

}  // namespace fovlab
