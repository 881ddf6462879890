// Stimuli from the lab's own images (protocols/stimuli/image_sequence.h): a folder of PNG or EXR
// images sampled by Ye et al. 2022's models (img-rmfr, img-hyperbolic, img-linear, img-kfr) at the
// display's geometry and the logged gaze. A session runs, its header records each image's SHA-256
// (log schema 9), it replays to its frame hashes and analyzes; replay refuses a changed or missing
// image by name; a bad folder is refused in one line naming the file. Images of 32x24 written here.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"
#include "core/digest.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "core/session_files.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "protocols/stimuli/image_sequence.h"
#include "protocols/stimuli/stimulus_library.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "tests/app/cli_test_support.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/renderer/vulkan_test_fixture.h"
#include "tests/support/fovlab_child.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::replay;

constexpr int kWidthPx = 32, kHeightPx = 24;

// A colour image whose pattern (a gradient and a checker of `index`-sized squares) differs by index,
// so each frame and each gaze shows something else.
Image pattern(int index, int width_px = kWidthPx, int height_px = kHeightPx) {
  Image image(width_px, height_px, 3);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) {
      const bool checker = ((x / (index + 2)) + (y / (index + 2))) % 2 == 0;
      image.at(x, y, 0) = float(x) / float(width_px - 1);
      image.at(x, y, 1) = float(y) / float(height_px - 1);
      image.at(x, y, 2) = checker ? 0.9f : 0.1f;
    }
  return image;
}

// `count` images frame_000.<extension>, ... in `folder`.
void write_sequence(const fs::path& folder, int count, const std::string& extension = ".png") {
  fs::create_directories(folder);
  for (int i = 0; i < count; ++i)
    write_image(folder / ("frame_00" + std::to_string(i) + extension), pattern(i));
}

// 2AFC, img-rmfr against img-hyperbolic over its outer pixel size, three frames (0.15 s at 20 fps).
std::string study_text(const std::string& scene = "images") {
  return R"([study]
name = "image_session"
seed = 11

[display]
width_px = 32
height_px = 24
refresh_hz = 60
width_mm = 120
height_mm = 90
viewing_distance_mm = 300

[stimulus]
duration_s = 0.15
frames_per_second = 20

[stimulus.reference]
method = "img-rmfr"
sigma = 1.5

[stimulus.test]
method = "img-hyperbolic"
inner_radius_deg = 3
outer_radius_deg = 6
blend_band_deg = 0.5

[levels]
parameter = "outer_pixel_size_px"
values = [3, 6]

[protocol]
kind = "2afc"
question = "same"
repeats = 1

[timing]
black_interval_s = 0.05
inter_trial_s = 0.05

[[block]]
scene = ")" + scene + "\"\n";
}

fs::path write_study(const fs::path& folder, const std::string& scene = "images") {
  return cli_test::write_file(folder / "study.toml", study_text(scene));
}

SessionOptions simulated(const fs::path& results) {
  const fs::path trace = results / "gaze.csv";
  fs::create_directories(results);
  std::ofstream(trace) << "time_s,x_px,y_px\n0,8.5,6.25\n0.1,20.5,14.75\n";
  return test::simulated_on_trace(results, trace);
}

// A PNG is sRGB-encoded and read in linear light; an EXR is read as it is.
TEST(ImageSequence, PngIsDecodedFromSrgbAndExrIsLinear) {
  const fs::path folder = fresh_folder("image-decode");
  Image grey(2, 1, 3);
  for (float& value : grey.pixels) value = 0.5f;
  write_image(folder / "grey.png", grey);
  write_image(folder / "grey.exr", grey);
  const SequenceImage png = read_sequence_image(folder / "grey.png");
  const SequenceImage exr = read_sequence_image(folder / "grey.exr");
  // 0.5 is stored as 128 / 255, whose sRGB decoding is 0.2158605.
  EXPECT_NEAR(png.linear.at(1, 0, 2), 0.2158605f, 1e-5f);
  EXPECT_EQ(exr.linear.at(1, 0, 2), 0.5f);
  EXPECT_EQ(png.sha256, sha256_hex(read_file(folder / "grey.png")));
  EXPECT_EQ(png.name, "grey.png");
  // Grey is repeated in R, G and B (the frame sampler reads three channels).
  Image one_channel(2, 1, 1);
  for (float& value : one_channel.pixels) value = 0.5f;
  write_image(folder / "grey1.png", one_channel);
  const SequenceImage grey_png = read_sequence_image(folder / "grey1.png");
  ASSERT_EQ(grey_png.linear.channels, 3);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(grey_png.linear.at(0, 0, c), 0.2158605f, 1e-5f) << c;
  // Sorted by name; other files are no images; frame i is image i, or the only one.
  std::ofstream(folder / "notes.txt") << "not an image";
  const std::vector<fs::path> files = image_sequence_files(folder);
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0].filename(), "grey.exr");
  EXPECT_EQ(sequence_image_index(3, 1), 1u);
  EXPECT_EQ(sequence_image_index(1, 2), 0u);
}

// The models on images take no parameters of their own, then exactly those of their sphere-traced
// twins (the first three of which are the sphere tracer's).
TEST(ImageSequence, ModelsOnImagesTakeTheirTwinsModelParameters) {
  for (size_t model = 0; model < kSamplingModelCount; ++model) {
    const MethodDescriptor& traced = describe(sampled_method(0, static_cast<SamplingModel>(model)));
    const MethodDescriptor& images = describe(sampled_method(2, static_cast<SamplingModel>(model)));
    EXPECT_EQ(images.name, "img-" + std::string(traced.name));
    EXPECT_EQ(images.scene_kind, SceneKind::image_sequence);
    EXPECT_TRUE(images.depends_on_gaze);
    EXPECT_EQ(images.needs_display, traced.needs_display);
    ASSERT_EQ(images.parameters.size() + 3, traced.parameters.size()) << images.name;
    for (size_t i = 0; i < images.parameters.size(); ++i) {
      EXPECT_EQ(images.parameters[i].key, traced.parameters[i + 3].key);
      EXPECT_EQ(images.parameters[i].default_value, traced.parameters[i + 3].default_value);
    }
  }
}

class ImageStimulusTest : public test::VulkanTest {};

// Every model renders the images: the same gaze gives the same bytes, another gaze other bytes,
// and frame i shows image i.
TEST_F(ImageStimulusTest, EveryModelSamplesTheImagesAtTheGaze) {
  const fs::path folder = fresh_folder("image-models") / "images";
  write_sequence(folder, 2);
  StimulusLibrary library(context());
  for (size_t model = 0; model < kSamplingModelCount; ++model) {
    const RenderMethod method = sampled_method(2, static_cast<SamplingModel>(model));
    SCOPED_TRACE(std::string(describe(method).name));
    StimulusSpec spec;
    spec.scene = folder.string();
    spec.parameters = default_parameters(method);
    spec.width_px = kWidthPx;
    spec.height_px = kHeightPx;
    spec.frame_count = 2;
    spec.frames_per_second = 20;
    if (StimulusDisplay* display = display_of(spec.parameters)) *display = StimulusDisplay{120, 90, 300};
    if (auto* layers = std::get_if<HyperbolicLayersModel>(&std::get<SampledParameters>(spec.parameters).model)) {
      layers->inner_radius_deg = 3;
      layers->outer_radius_deg = 6;
      layers->blend_band_deg = 0.5;
    }
    if (auto* linear = std::get_if<LinearFalloffModel>(&std::get<SampledParameters>(spec.parameters).model)) {
      linear->inner_radius_deg = 3;
      linear->outer_radius_deg = 6;
      linear->min_probability = 0.2;
    }
    library.prepare({{int(model), spec}});
    const auto at = [&](int frame, double x_px, double y_px) {
      GazeSample gaze;
      gaze.x_px = x_px;
      gaze.y_px = y_px;
      return library.render(spec, StimulusImage{frame, 0, gaze}).hash;
    };
    const std::string centre = at(0, 16, 12);
    EXPECT_EQ(at(0, 16, 12), centre);
    EXPECT_NE(at(0, 2, 2), centre);
    EXPECT_NE(at(1, 16, 12), centre);
  }
}

// A session of images runs, records every image's SHA-256, replays to its frame hashes and analyzes.
TEST(ImageSession, RunsReplaysAndAnalyzes) {
  const fs::path folder = fresh_folder("image-session");
  write_sequence(folder / "images", 3);
  const StudyConfig config = parse_study_config_file(write_study(folder).string(), renderer_scene_catalog());
  const SessionOutcome outcome = run_session(config, simulated(folder / "results"));
  ASSERT_TRUE(outcome.finished);

  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  EXPECT_EQ(record.header.value("schema_version", 0), log_schema_version);
  const nlohmann::json& images = record.header.at("image_hashes");
  const std::string images_folder = (folder / "images").lexically_normal().string();
  ASSERT_TRUE(images.contains(images_folder)) << images.dump();
  ASSERT_EQ(images.at(images_folder).size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const std::string name = "frame_00" + std::to_string(i) + ".png";
    EXPECT_EQ(images.at(images_folder).at(name), sha256_hex(read_file(folder / "images" / name))) << name;
  }

  const ReplayOutcome replayed = replay(outcome.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences[0]);
  EXPECT_GT(replayed.presents_checked, 0);
  EXPECT_EQ(replayed.trials, 2);

  analysis::AnalysisOptions options;
  options.bootstrap_samples = 0;
  const analysis::AnalysisResult result = analysis::analyse_study(analysis::load_study({outcome.log_path}), options);
  ASSERT_EQ(result.conditions.size(), 2u);
  uint64_t trials = 0;
  for (const analysis::ConditionRow& row : result.conditions) {
    EXPECT_EQ(row.method, "img-hyperbolic");
    trials += row.n;
  }
  EXPECT_EQ(trials, 2u);

  // An image changed since the session: replay refuses, in one line naming it (exit code 2).
  write_image(folder / "images" / "frame_001.png", pattern(7));
  const cli_test::CommandResult changed = cli_test::run("replay " + outcome.log_path);
  cli_test::expect_one_line_error(changed, "frame_001.png: changed since the session");
  // One missing: the same, naming it.
  fs::remove(folder / "images" / "frame_002.png");
  write_image(folder / "images" / "frame_001.png", pattern(1));
  cli_test::expect_one_line_error(cli_test::run("replay " + outcome.log_path), "frame_002.png: missing");
}

// The header records the bytes the session read, not the folder as it is a moment later: an image
// rewritten after the stimuli were read (the run stopped at its "prepared" pause point) leaves the
// log naming the image the participant saw, and replay then refuses the rewritten one. Before,
// the header hashed the folder again after reading it, so the log named an image never shown.
TEST(ImageSession, TheHeaderRecordsTheImagesTheSessionRead) {
  const fs::path folder = fresh_folder("image-read-once");
  write_sequence(folder / "images", 3);
  const std::string shown_hash = sha256_hex(read_file(folder / "images" / "frame_001.png"));
  const fs::path results = folder / "results";
  const SessionOptions options = simulated(results);  // writes the gaze trace
  const pid_t run = test::start_fovlab({"run", write_study(folder).string(), "--participant", "P1", "--observer",
                                        "simulated", "--headless", "--results", results.string(), "--gaze",
                                        options.gaze},
                                       "prepared", folder / "run-output.txt");
  ASSERT_TRUE(test::wait_until_stopped(run)) << read_file(folder / "run-output.txt");
  write_image(folder / "images" / "frame_001.png", pattern(7));
  ASSERT_NE(sha256_hex(read_file(folder / "images" / "frame_001.png")), shown_hash);
  kill(run, SIGCONT);
  ASSERT_EQ(test::exit_code(run), 0) << read_file(folder / "run-output.txt");

  const std::string log_path = session_log_path(results.string(), "image_session", "P1");
  const SessionRecord record = read_session_record(read_event_log(log_path));
  const std::string images_folder = (folder / "images").lexically_normal().string();
  EXPECT_EQ(record.header.at("image_hashes").at(images_folder).at("frame_001.png"), shown_hash);
  cli_test::expect_one_line_error(cli_test::run("replay " + log_path), "frame_001.png: changed since the session");
  // The image the session showed, restored: the log replays to its frame hashes.
  write_image(folder / "images" / "frame_001.png", pattern(1));
  const ReplayOutcome replayed = replay(log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences[0]);
}

// A missing or empty folder, an image that does not decode, images of another size, too few
// images: `fovlab validate` refuses each in one line naming the folder or file (exit code 2).
TEST(ImageSession, BadFoldersAreRefusedNamingTheFile) {
  const fs::path folder = fresh_folder("image-bad");
  const fs::path study = write_study(folder);
  const auto validate = [&] { return cli_test::run("validate " + study.string()); };
  cli_test::expect_one_line_error(validate(), "scene: expected a folder of .png or .exr images");

  fs::create_directories(folder / "images");
  cli_test::expect_one_line_error(validate(), "images: no .png or .exr image in it");

  write_sequence(folder / "images", 3, ".exr");
  std::ofstream(folder / "images" / "frame_001.exr", std::ios::binary) << "not an EXR at all";
  cli_test::expect_one_line_error(validate(), "frame_001.exr: cannot read image");

  write_image(folder / "images" / "frame_001.exr", pattern(1, 40, 30));
  cli_test::expect_one_line_error(validate(), "frame_001.exr: 40x30 pixels: expected 32x24");

  fs::remove(folder / "images" / "frame_002.exr");
  write_image(folder / "images" / "frame_001.exr", pattern(1));
  cli_test::expect_one_line_error(validate(), "images: 2 images: expected one (a still) or 3 or more");

  // One image is a still, shown for every frame.
  fs::remove(folder / "images" / "frame_001.exr");
  const cli_test::CommandResult still = validate();
  EXPECT_EQ(still.exit_code, 0) << still.err;
  // The images shown are held in memory: more than there is is refused before the first trial.
  cli_test::expect_one_line_error(
      cli_test::run("validate " + study.string(), "FOVLAB_MEMORY_LIMIT_BYTES=5000"),
      "images: 1 images of 32x24 px as linear RGB floats: needs about");
}

}  // namespace
}  // namespace fovlab
