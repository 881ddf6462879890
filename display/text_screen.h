#pragma once
// Screens between trials: centred text (instructions, a question with its answer keys, "Rest: 30 s",
// a countdown), a fixation cross, black. Drawn on the CPU with OpenImageIO's FreeType text
// renderer into sRGB-encoded RGBA8 frames any presenter shows as they are.
#include <string>
#include <vector>

#include "core/rgba8_frame.h"

namespace fovlab {

struct TextScreenStyle {
  // Nominal font size as a fraction of the frame height, never below min_font_px (12 px keeps a
  // 320x180 screen readable). The size shrinks (down to 8 px) when the wrapped text would not fit
  // the frame's height.
  double font_height_fraction = 0.04;
  int min_font_px = 12;
  int font_px = 0;                // > 0: this size instead
  double margin_fraction = 0.05;  // each side; text wraps to the rest of the width
  double line_spacing = 1.3;      // baseline to baseline, in font sizes
  unsigned char grey = 204;       // sRGB-encoded text grey (light grey on black)
  std::string font_path;          // empty: find_font_path()
};

// A TrueType font file: $FOVLAB_FONT when set, else DejaVu Sans (Debian: fonts-dejavu-core), else
// Liberation Sans or FreeSans. Throws std::runtime_error naming the package when none exists.
std::string find_font_path();

// `text` split into lines that fit max_width_px at font_px: paragraphs at '\n', greedy word wrap at
// spaces, a word longer than a line broken between characters. Empty paragraphs stay empty lines.
std::vector<std::string> wrap_text(const std::string& text, int max_width_px, int font_px,
                                   const std::string& font_path);

// Light grey text on black, every line centred horizontally, the block centred vertically.
Rgba8Frame render_text_screen(int width_px, int height_px, const std::string& text, const TextScreenStyle& style = {});

// All black, alpha 255.
Rgba8Frame black_frame(int width_px, int height_px);

// Black with a small grey cross at the centre (arms about 1.5% of the height, at least 2 px; the
// stroke height/360, at least 1 px), in the style's grey.
Rgba8Frame fixation_cross_frame(int width_px, int height_px, const TextScreenStyle& style = {});

// Black with an eye-tracker validation target centred on (x_px, y_px) (pixel coordinates, origin
// top left): a disk of radius_px in the style's grey with a black dot of a quarter of the radius
// (at least 1 px) at its centre, where the participant is asked to look. A pixel is lit when its
// centre lies in the disk.
Rgba8Frame validation_target_frame(int width_px, int height_px, double x_px, double y_px, double radius_px,
                                   const TextScreenStyle& style = {});

}  // namespace fovlab
