#pragma once
// Gaze from a Pupil Core eye tracker (Pupil Capture / Service) through its Network API, mapped onto
// a surface (the Surface Tracker plugin, surface named after the screen, "screen" by default).
//
// Protocol (docs.pupil-labs.com/core/developer/network-api): a REQ socket to Pupil Remote
// (tcp://HOST:PORT, default 50020) sends "SUB_PORT" and receives the port of the IPC backbone's
// publisher; a SUB socket connects there and subscribes to "surfaces.<surface>". Each message is
// multipart: the topic, then a msgpack map whose "gaze_on_surfaces" array holds entries with
// "norm_pos" [x, y] (surface-normalised, origin bottom-left, y up), "on_surf", "confidence" and
// "timestamp" (Pupil time). The entry with the latest timestamp of a message is used.
//
// Pixels: x_px = x * width, y_px = (1 - y) * height. confidence < min_confidence -> invalid
// "low_confidence" (blinks look like this); on_surf false -> invalid "off_screen"; a non-finite
// position -> invalid "not_finite" (position 0, 0).
//
// A background thread receives messages and keeps the latest. sample(t) never blocks for long: it
// returns the latest sample stamped with the session time t, or an invalid "no_data" sample at
// (0, 0) with no acquired_s when nothing has arrived yet or the latest arrived more than
// staleness_s (wall clock) ago.
//
// Clocks: at start-up the source asks Pupil Remote for Pupil time ("t"; the answer is the time in
// seconds as text) and reads the session clock just before the request and just after the answer.
// Pupil time is taken to have been read at the midpoint of that round trip:
//   clock_offset_s = pupil_time - (session_before + session_after) / 2,
// so a sample's acquired_s = its Pupil timestamp - clock_offset_s, off by at most half the round
// trip (clock_sync_rtt_s; ~0.1-1 ms on one machine) plus the drift of the two clocks since (Pupil
// time is a monotonic clock too, so this stays small over a session). A gaze entry without a
// timestamp is stamped with its arrival, mapped through the process's steady clock.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "protocols/gaze/gaze_source.h"

namespace fovlab {

struct PupilGazeOptions {
  std::string host = "127.0.0.1";
  int port = 50020;                // Pupil Remote
  std::string surface = "screen";  // Surface Tracker surface that covers the screen
  double min_confidence = 0.6;
  double staleness_s = 0.1;  // wall seconds after which the latest sample no longer counts
  double timeout_s = 2.0;    // Pupil Remote must answer SUB_PORT and "t" within this
  // The session clock in seconds, called on the constructing thread only (the time sync); empty:
  // the process's steady clock.
  std::function<double()> session_clock;
};

// Decodes the msgpack payload of a "surfaces.<name>" message into a sample (time_s = 0) from the
// gaze entry with the latest timestamp; acquired_s holds that timestamp as it is (Pupil time), or
// nullopt when the entry has none. nullopt when the message has no gaze entry.
// std::runtime_error when the payload is not such a message.
std::optional<GazeSample> decode_pupil_surface_gaze(std::string_view payload, double min_confidence, int width_px,
                                                    int height_px);

class PupilGazeSource final : public GazeSource {
 public:
  // Connects, asks Pupil Remote for the subscription port and for Pupil time (the clock mapping).
  // InputError for bad options, an address ZeroMQ refuses, no answer within timeout_s ("pupil:HOST:PORT: no answer from Pupil
  // Remote within 2 s (is Pupil Capture running with the Network API plugin?)") or a bad answer.
  PupilGazeSource(PupilGazeOptions options, int width_px, int height_px);
  ~PupilGazeSource() override;  // stops the receiver thread and closes the sockets (within ~20 ms)
  PupilGazeSource(const PupilGazeSource&) = delete;
  PupilGazeSource& operator=(const PupilGazeSource&) = delete;

  GazeSample sample(double time_s) override;  // thread-safe with the receiver
  std::string describe() const override;      // "pupil:HOST:PORT"

  uint64_t messages_received() const;  // surface messages with gaze accepted so far
  // Pupil time minus session time, measured at start-up, and the round trip of that request.
  double clock_offset_s() const;
  double clock_sync_rtt_s() const;
  uint64_t messages_malformed() const;  // messages on our topic that could not be decoded

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fovlab
