// Text screens, the fixation cross and black frames: where the ink is, word wrap, sizes.
#include <gtest/gtest.h>

#include <string>

#include "display/text_screen.h"

namespace fovlab {
namespace {

bool is_black(const Rgba8Frame& frame, int x, int y) {
  const uint8_t* p =
      frame.rgba.data() + (static_cast<size_t>(y) * static_cast<size_t>(frame.width) + static_cast<size_t>(x)) * 4;
  return p[0] == 0 && p[1] == 0 && p[2] == 0;
}

// Non-black pixels in [x0, x1) x [y0, y1).
int ink(const Rgba8Frame& frame, int x0, int y0, int x1, int y1) {
  int count = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) count += is_black(frame, x, y) ? 0 : 1;
  }
  return count;
}

bool all_opaque(const Rgba8Frame& frame) {
  for (size_t i = 3; i < frame.rgba.size(); i += 4) {
    if (frame.rgba[i] != 255) return false;
  }
  return true;
}

const char* kLongInstructions =
    "In each trial you see two images one after the other. Press A if the first image looked sharper "
    "and B if the second did. Keep your eyes on the cross in the middle of the screen. There is no right "
    "or wrong answer: go with your first impression.";

TEST(TextScreen, CentredTextAndBlackCorners) {
  for (auto [width, height] : {std::pair{1280, 720}, std::pair{320, 180}}) {
    const Rgba8Frame frame = render_text_screen(width, height, "Which image was sharper?\nA: first    B: second");
    ASSERT_EQ(frame.width, width);
    ASSERT_EQ(frame.height, height);
    EXPECT_TRUE(all_opaque(frame));
    EXPECT_GT(ink(frame, width / 4, height / 3, 3 * width / 4, 2 * height / 3), 50) << width << "x" << height;
    const int cw = width / 8, ch = height / 8;
    EXPECT_EQ(ink(frame, 0, 0, cw, ch), 0);
    EXPECT_EQ(ink(frame, width - cw, 0, width, ch), 0);
    EXPECT_EQ(ink(frame, 0, height - ch, cw, height), 0);
    EXPECT_EQ(ink(frame, width - cw, height - ch, width, height), 0);
    // Light grey: the brightest ink is the style's grey, never white.
    uint8_t brightest = 0;
    for (size_t i = 0; i < frame.rgba.size(); i += 4) brightest = std::max(brightest, frame.rgba[i]);
    EXPECT_EQ(brightest, TextScreenStyle{}.grey);
  }
}

TEST(TextScreen, WordWrapKeepsTextInsideTheFrame) {
  const Rgba8Frame frame = render_text_screen(320, 180, kLongInstructions);
  // Margins are 5% a side (16 px, 9 px): the outer 8 and 4 pixels have no ink.
  EXPECT_EQ(ink(frame, 0, 0, 8, 180), 0);
  EXPECT_EQ(ink(frame, 312, 0, 320, 180), 0);
  EXPECT_EQ(ink(frame, 0, 0, 320, 4), 0);
  EXPECT_EQ(ink(frame, 0, 176, 320, 180), 0);
  EXPECT_GT(ink(frame, 0, 0, 320, 180), 500);

  const std::string font = find_font_path();
  const std::vector<std::string> lines = wrap_text(kLongInstructions, 288, 12, font);
  EXPECT_GT(lines.size(), 3u);
  std::string rejoined;
  for (const std::string& line : lines) rejoined += (rejoined.empty() ? "" : " ") + line;
  EXPECT_EQ(rejoined, kLongInstructions);  // wrapping moves words, never drops them
}

TEST(TextScreen, ParagraphsAndLongWords) {
  const std::string font = find_font_path();
  EXPECT_EQ(wrap_text("Rest: 30 s\n\nPress space", 1000, 20, font),
            (std::vector<std::string>{"Rest: 30 s", "", "Press space"}));
  const std::vector<std::string> broken = wrap_text("Supercalifragilisticexpialidocious", 60, 16, font);
  EXPECT_GT(broken.size(), 1u);
  std::string rejoined;
  for (const std::string& line : broken) rejoined += line;
  EXPECT_EQ(rejoined, "Supercalifragilisticexpialidocious");
  // A countdown digit at a huge size still fits.
  const Rgba8Frame countdown = render_text_screen(320, 180, "3", TextScreenStyle{0.5});
  EXPECT_GT(ink(countdown, 120, 45, 200, 135), 200);
  EXPECT_EQ(ink(countdown, 0, 0, 320, 8), 0);
}

TEST(TextScreen, TooMuchTextShrinksToFit) {
  std::string text;
  for (int i = 0; i < 6; ++i) text += std::string(kLongInstructions) + "\n";
  const Rgba8Frame frame = render_text_screen(640, 360, text);
  EXPECT_EQ(ink(frame, 0, 0, 640, 2), 0);
  EXPECT_EQ(ink(frame, 0, 358, 640, 360), 0);
}

TEST(TextScreen, BlackFrame) {
  const Rgba8Frame frame = black_frame(64, 32);
  ASSERT_EQ(frame.rgba.size(), 64u * 32u * 4u);
  EXPECT_EQ(ink(frame, 0, 0, 64, 32), 0);
  EXPECT_TRUE(all_opaque(frame));
}

TEST(TextScreen, FixationCrossAtTheCentre) {
  const Rgba8Frame frame = fixation_cross_frame(1280, 720);
  EXPECT_TRUE(all_opaque(frame));
  EXPECT_FALSE(is_black(frame, 640, 360));
  EXPECT_FALSE(is_black(frame, 640 - 8, 360));
  EXPECT_FALSE(is_black(frame, 640, 360 + 8));
  EXPECT_TRUE(is_black(frame, 640 - 8, 360 - 8));  // between the arms
  const int count = ink(frame, 0, 0, 1280, 720);
  EXPECT_GT(count, 40);
  EXPECT_LT(count, 200);  // small
  EXPECT_EQ(ink(frame, 0, 0, 600, 720), 0);
  const Rgba8Frame tiny = fixation_cross_frame(320, 180);
  EXPECT_FALSE(is_black(tiny, 160, 90));
}

}  // namespace
}  // namespace fovlab

namespace fovlab {
namespace {

// A frame too small for the text even at the smallest font: drawn without crashing (OpenImageIO
// asserts on text wholly outside an image), and nothing is drawn outside the frame.
TEST(TextScreen, FramesTooSmallForTheTextStillRender) {
  const std::string question = "Was the quality the same in both sequences?\n\nS: same    D: different";
  for (const auto& [width, height] : {std::pair{8, 8}, std::pair{16, 9}, std::pair{64, 36}, std::pair{40, 30}}) {
    const Rgba8Frame frame = render_text_screen(width, height, question);
    EXPECT_EQ(frame.width, width);
    EXPECT_EQ(frame.rgba.size(), static_cast<size_t>(width * height * 4));
  }
}

}  // namespace
}  // namespace fovlab
