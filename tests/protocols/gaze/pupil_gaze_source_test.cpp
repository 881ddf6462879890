#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "protocols/gaze/gaze_spec.h"
#include "protocols/gaze/pupil_gaze_source.h"
#include "tests/protocols/gaze/fake_pupil_publisher.h"

namespace fovlab {
namespace {

using fovlab::testing::FakePupilPublisher;
using fovlab::testing::FakeSurfaceGaze;
using fovlab::testing::pack_surface_message;

constexpr int width = 1920;
constexpr int height = 1080;

PupilGazeOptions options_for(const FakePupilPublisher& fake) {
  PupilGazeOptions options;
  options.port = fake.remote_port();
  return options;
}

FakeSurfaceGaze gaze(double x, double y, double confidence = 0.95, bool on_surf = true, double timestamp = 100.0) {
  FakeSurfaceGaze entry;
  entry.x = x;
  entry.y = y;
  entry.confidence = confidence;
  entry.on_surf = on_surf;
  entry.timestamp = timestamp;
  return entry;
}

// Publishes the message until the source has accepted one more message than before (bounded).
// First waits until copies of an earlier message still in flight have arrived (TCP keeps the order,
// so after that the next accepted message is this one).
void deliver(FakePupilPublisher& fake, PupilGazeSource& source, const std::vector<FakeSurfaceGaze>& entries,
             const std::string& surface = "screen") {
  uint64_t before = source.messages_received();
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(15));
    const uint64_t now = source.messages_received();
    if (now == before) break;
    before = now;
  }
  ASSERT_TRUE(fake.publish_until("surfaces." + surface, pack_surface_message(surface, entries), [&] {
    return source.messages_received() > before;
  })) << "the source received nothing within 2 s";
}

TEST(GazePupil, ValidGazeMapsToScreenPixels) {
  FakePupilPublisher fake;
  PupilGazeSource source(options_for(fake), width, height);
  EXPECT_EQ(source.describe(), "pupil:127.0.0.1:" + std::to_string(fake.remote_port()));
  EXPECT_EQ(fake.requests_answered(), 1);

  deliver(fake, source, {gaze(0.25, 0.75)});
  GazeSample sample = source.sample(12.5);
  EXPECT_TRUE(sample.valid);
  EXPECT_EQ(sample.invalid_reason, "");
  EXPECT_DOUBLE_EQ(sample.time_s, 12.5);  // stamped with the session time
  EXPECT_DOUBLE_EQ(sample.x_px, 480.0);
  EXPECT_DOUBLE_EQ(sample.y_px, 270.0);  // y up on the surface, down on the screen

  // Of several entries, the one with the latest timestamp counts.
  deliver(fake, source,
          {gaze(0.1, 0.1, 0.9, true, 2.0), gaze(0.9, 0.9, 0.9, true, 3.0), gaze(0.5, 0.5, 0.9, true, 1.0)});
  sample = source.sample(13.0);
  EXPECT_TRUE(sample.valid);
  EXPECT_DOUBLE_EQ(sample.x_px, 0.9 * width);
  EXPECT_NEAR(sample.y_px, 0.1 * height, 1e-9);
  EXPECT_EQ(source.messages_malformed(), 0u);
}

TEST(GazePupil, LowConfidenceAndOffSurfaceAreInvalid) {
  FakePupilPublisher fake;
  PupilGazeSource source(options_for(fake), width, height);

  deliver(fake, source, {gaze(0.5, 0.5, 0.59)});  // below the default minimum of 0.6
  GazeSample sample = source.sample(1.0);
  EXPECT_FALSE(sample.valid);
  EXPECT_EQ(sample.invalid_reason, "low_confidence");
  EXPECT_DOUBLE_EQ(sample.x_px, 960.0);

  deliver(fake, source, {gaze(1.2, -0.1, 0.99, false)});
  sample = source.sample(2.0);
  EXPECT_FALSE(sample.valid);
  EXPECT_EQ(sample.invalid_reason, "off_screen");
  EXPECT_DOUBLE_EQ(sample.x_px, 1.2 * width);
  EXPECT_DOUBLE_EQ(sample.y_px, 1.1 * height);

  deliver(fake, source, {gaze(0.5, 0.5, 0.6)});  // exactly the minimum is enough
  EXPECT_TRUE(source.sample(3.0).valid);
}

TEST(GazePupil, NoDataBeforeTheFirstMessageAndWhenStale) {
  FakePupilPublisher fake;
  PupilGazeOptions options = options_for(fake);
  options.staleness_s = 0.2;
  PupilGazeSource source(options, width, height);
  GazeSample sample = source.sample(0.5);
  EXPECT_FALSE(sample.valid);
  EXPECT_EQ(sample.invalid_reason, "no_data");
  EXPECT_DOUBLE_EQ(sample.time_s, 0.5);

  deliver(fake, source, {gaze(0.5, 0.5)});
  EXPECT_TRUE(source.sample(1.0).valid);
  std::this_thread::sleep_for(std::chrono::milliseconds(350));  // nothing published since
  sample = source.sample(1.5);
  EXPECT_FALSE(sample.valid);
  EXPECT_EQ(sample.invalid_reason, "no_data");
}

TEST(GazePupil, OtherSurfacesAndMalformedMessagesAreIgnored) {
  FakePupilPublisher fake;
  PupilGazeOptions options = options_for(fake);
  options.staleness_s = 10.0;
  PupilGazeSource source(options, width, height);
  deliver(fake, source, {gaze(0.25, 0.5)});

  // "surfaces.screen2" matches the subscription prefix but is another surface.
  for (int i = 0; i < 25; ++i) {
    fake.publish_gaze("screen2", {gaze(0.75, 0.5)});
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // A payload that is not a surface message is counted, not used.
  ASSERT_TRUE(fake.publish_until("surfaces.screen", "not msgpack at all \xc1",
                                 [&] { return source.messages_malformed() > 0; }));
  const GazeSample sample = source.sample(1.0);
  EXPECT_TRUE(sample.valid);
  EXPECT_DOUBLE_EQ(sample.x_px, 480.0);
}

TEST(GazePupil, NoPupilRemoteIsAnInputErrorAfterTheTimeout) {
  const int port = fovlab::testing::unused_local_port();
  PupilGazeOptions options;
  options.port = port;
  options.timeout_s = 0.3;
  const auto start = std::chrono::steady_clock::now();
  try {
    PupilGazeSource source(options, width, height);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "pupil:127.0.0.1:" + std::to_string(port) +
                  ": no answer from Pupil Remote within 0.3 s (is Pupil Capture running with the Network API plugin?)");
  }
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_GE(elapsed.count(), 0.25);
  EXPECT_LT(elapsed.count(), 1.5);
}

TEST(GazePupil, BadOptionsAreInputErrors) {
  PupilGazeOptions options;
  options.port = 70000;
  EXPECT_THROW(PupilGazeSource(options, width, height), InputError);
  options = {};
  options.min_confidence = 1.5;
  EXPECT_THROW(PupilGazeSource(options, width, height), InputError);
  options = {};
  options.host = "not a host name";
  options.timeout_s = 0.3;
  EXPECT_THROW(PupilGazeSource(options, width, height), InputError);
}

TEST(GazePupil, DestructorReturnsPromptly) {
  FakePupilPublisher fake;
  auto source = std::make_unique<PupilGazeSource>(options_for(fake), width, height);
  deliver(fake, *source, {gaze(0.5, 0.5)});
  const auto start = std::chrono::steady_clock::now();
  source.reset();
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_LT(elapsed.count(), 0.5);
}

TEST(GazePupil, MadeFromASpec) {
  FakePupilPublisher fake;
  const GazeSpec spec = parse_gaze_spec("pupil:127.0.0.1:" + std::to_string(fake.remote_port()));
  const std::unique_ptr<GazeSource> source = make_gaze_source(spec, width, height, 1);
  EXPECT_EQ(source->describe(), "pupil:127.0.0.1:" + std::to_string(fake.remote_port()));
  EXPECT_EQ(fake.requests_answered(), 1);
  // The surface and the confidence floor from the spec reach the source, and the log's description.
  FakePupilPublisher other;
  const GazeSpec set =
      parse_gaze_spec("pupil:127.0.0.1:" + std::to_string(other.remote_port()) + ",surface=monitor,min_confidence=0.8");
  EXPECT_EQ(make_gaze_source(set, width, height, 1)->describe(),
            "pupil:127.0.0.1:" + std::to_string(other.remote_port()) + ",surface=monitor,min_confidence=0.8");
}

TEST(GazePupil, DecodesPayloadsDirectly) {
  EXPECT_EQ(decode_pupil_surface_gaze(pack_surface_message("screen", {}), 0.6, width, height), std::nullopt);
  const std::optional<GazeSample> sample =
      decode_pupil_surface_gaze(pack_surface_message("screen", {gaze(0.0, 1.0)}), 0.6, 100, 50);
  ASSERT_TRUE(sample.has_value());
  EXPECT_TRUE(sample->valid);
  EXPECT_DOUBLE_EQ(sample->x_px, 0.0);
  EXPECT_DOUBLE_EQ(sample->y_px, 0.0);
  const std::optional<GazeSample> nan_sample = decode_pupil_surface_gaze(
      pack_surface_message("screen", {gaze(std::numeric_limits<double>::quiet_NaN(), 0.5)}), 0.6, 100, 50);
  ASSERT_TRUE(nan_sample.has_value());
  EXPECT_EQ(nan_sample->invalid_reason, "not_finite");
  EXPECT_THROW(decode_pupil_surface_gaze("\x01", 0.6, width, height), std::runtime_error);
  EXPECT_THROW(decode_pupil_surface_gaze("", 0.6, width, height), std::runtime_error);
}

}  // namespace
}  // namespace fovlab

namespace fovlab {
namespace {

// Pupil time is mapped to the session clock at start-up with Pupil Remote's "t": the offset is
// Pupil time minus the midpoint of the request's round trip, so a sample's acquisition time on the
// session clock is its Pupil timestamp minus that offset, within half the round trip.
TEST(PupilTimeSync, MapsPupilTimestampsToTheSessionClock) {
  constexpr double pupil_minus_steady_s = 12345.25;  // Pupil's clock runs from another origin
  FakePupilPublisher fake(pupil_minus_steady_s);
  PupilGazeOptions options = options_for(fake);
  options.staleness_s = 10.0;
  // A session clock that started 3 s ago on the steady clock.
  const double session_origin_s = fovlab::testing::steady_now_s() - 3.0;
  options.session_clock = [&] { return fovlab::testing::steady_now_s() - session_origin_s; };
  PupilGazeSource source(options, width, height);
  EXPECT_EQ(fake.time_requests_answered(), 1);
  EXPECT_GE(source.clock_sync_rtt_s(), 0.0);
  EXPECT_LT(source.clock_sync_rtt_s(), 0.5);
  // Pupil time - session time = (steady + 12345.25) - (steady - origin).
  const double expected_offset_s = pupil_minus_steady_s + session_origin_s;
  EXPECT_NEAR(source.clock_offset_s(), expected_offset_s, 0.5 * source.clock_sync_rtt_s() + 1e-6);

  // A sample the tracker took at session time 2.75 s carries that time, whatever its Pupil stamp.
  const double taken_session_s = 2.75;
  const double pupil_stamp_s = fake.pupil_time_at(session_origin_s + taken_session_s);
  deliver(fake, source, {gaze(0.5, 0.5, 0.95, true, pupil_stamp_s)});
  const GazeSample sample = source.sample(3.5);
  ASSERT_TRUE(sample.valid);
  EXPECT_DOUBLE_EQ(sample.time_s, 3.5);  // the query time stays the session's
  ASSERT_TRUE(sample.acquired_s.has_value());
  EXPECT_NEAR(*sample.acquired_s, taken_session_s, 0.5 * source.clock_sync_rtt_s() + 1e-6);
  EXPECT_DOUBLE_EQ(*sample.acquired_s, pupil_stamp_s - source.clock_offset_s());
}

TEST(PupilTimeSync, NoSampleHasNoAcquisitionTime) {
  FakePupilPublisher fake;
  PupilGazeSource source(options_for(fake), width, height);
  const GazeSample sample = source.sample(0.25);
  EXPECT_EQ(sample.invalid_reason, "no_data");
  EXPECT_FALSE(sample.acquired_s.has_value());
}

TEST(PupilTimeSync, ABadTimeAnswerIsAnInputError) {
  FakePupilPublisher fake(0.0, "not a time");
  try {
    PupilGazeSource source(options_for(fake), width, height);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "pupil:127.0.0.1:" + std::to_string(fake.remote_port()) +
                  ": Pupil Remote answered t with \"not a time\", expected Pupil time in seconds");
  }
}

TEST(PupilTimeSync, DecodedSampleKeepsThePupilTimestamp) {
  const std::optional<GazeSample> sample =
      decode_pupil_surface_gaze(pack_surface_message("screen", {gaze(0.5, 0.5, 0.9, true, 4321.5)}), 0.6, 100, 50);
  ASSERT_TRUE(sample.has_value());
  ASSERT_TRUE(sample->acquired_s.has_value());
  EXPECT_DOUBLE_EQ(*sample->acquired_s, 4321.5);
}

}  // namespace
}  // namespace fovlab
