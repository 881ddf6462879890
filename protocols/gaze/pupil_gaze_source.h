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
// (0, 0) when nothing has arrived yet or the latest arrived more than staleness_s (wall clock) ago.
// Pupil timestamps are not converted to session time: the latency of the tracker is not corrected.
#include <cstdint>
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
  double timeout_s = 2.0;    // Pupil Remote must answer SUB_PORT within this
};

// Decodes the msgpack payload of a "surfaces.<name>" message into a sample (time_s = 0) from the
// gaze entry with the latest timestamp; nullopt when the message has no gaze entry.
// std::runtime_error when the payload is not such a message.
std::optional<GazeSample> decode_pupil_surface_gaze(std::string_view payload, double min_confidence, int width_px,
                                                    int height_px);

class PupilGazeSource final : public GazeSource {
 public:
  // Connects and asks Pupil Remote for the subscription port. InputError for bad options, an
  // address ZeroMQ refuses, no answer within timeout_s ("pupil:HOST:PORT: no answer from Pupil
  // Remote within 2 s (is Pupil Capture running with the Network API plugin?)") or a bad answer.
  PupilGazeSource(PupilGazeOptions options, int width_px, int height_px);
  ~PupilGazeSource() override;  // stops the receiver thread and closes the sockets (within ~20 ms)
  PupilGazeSource(const PupilGazeSource&) = delete;
  PupilGazeSource& operator=(const PupilGazeSource&) = delete;

  GazeSample sample(double time_s) override;  // thread-safe with the receiver
  std::string describe() const override;      // "pupil:HOST:PORT"

  uint64_t messages_received() const;  // surface messages with gaze accepted so far
  uint64_t messages_malformed() const;  // messages on our topic that could not be decoded

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fovlab
