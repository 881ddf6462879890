#include "display/text_screen.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace fovlab {

namespace {

constexpr int kSmallestFontPx = 8;

int text_width_px(const std::string& text, int font_px, const std::string& font_path) {
  if (text.empty()) return 0;
  const OIIO::ROI roi = OIIO::ImageBufAlgo::text_size(text, font_px, font_path);
  if (!roi.defined()) throw std::runtime_error("text screen: cannot measure text with font " + font_path);
  return roi.width();
}

// Byte length of the UTF-8 sequence starting at text[i] (1 for malformed bytes).
size_t utf8_length(const std::string& text, size_t i) {
  const auto lead = static_cast<unsigned char>(text[i]);
  size_t length = lead < 0x80 ? 1 : (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xE ? 3 : (lead >> 3) == 0x1E ? 4 : 1;
  return std::min(length, text.size() - i);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

int font_px_for(const TextScreenStyle& style, int height_px) {
  if (style.font_px > 0) return style.font_px;
  return std::max(style.min_font_px, static_cast<int>(std::lround(style.font_height_fraction * height_px)));
}

}  // namespace

std::string find_font_path() {
  if (const char* chosen = std::getenv("FOVLAB_FONT"); chosen && *chosen) {
    if (!std::filesystem::is_regular_file(chosen)) {
      throw std::runtime_error(std::string("FOVLAB_FONT=") + chosen + ": no such font file");
    }
    return chosen;
  }
  for (const char* candidate : {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                                "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
                                "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
                                "/usr/share/fonts/truetype/freefont/FreeSans.ttf"}) {
    if (std::filesystem::is_regular_file(candidate)) return candidate;
  }
  throw std::runtime_error(
      "text screen: no font found (expected /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf from the Debian package "
      "fonts-dejavu-core, or FOVLAB_FONT=<file.ttf>)");
}

std::vector<std::string> wrap_text(const std::string& text, int max_width_px, int font_px,
                                   const std::string& font_path) {
  std::vector<std::string> lines;
  for (const std::string& paragraph : split(text, '\n')) {
    std::string line;
    for (const std::string& word : split(paragraph, ' ')) {
      if (word.empty()) continue;  // runs of spaces
      const std::string candidate = line.empty() ? word : line + " " + word;
      if (text_width_px(candidate, font_px, font_path) <= max_width_px) {
        line = candidate;
        continue;
      }
      if (!line.empty()) lines.push_back(line);
      line.clear();
      // The word alone: broken between characters while it is too wide.
      for (size_t i = 0; i < word.size();) {
        const size_t length = utf8_length(word, i);
        const std::string longer = line + word.substr(i, length);
        if (!line.empty() && text_width_px(longer, font_px, font_path) > max_width_px) {
          lines.push_back(line);
          line.clear();
          continue;
        }
        line = longer;
        i += length;
      }
    }
    lines.push_back(line);
  }
  return lines;
}

Rgba8Frame black_frame(int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0) throw std::invalid_argument("black_frame: size must be positive");
  return Rgba8Frame(width_px, height_px);
}

Rgba8Frame render_text_screen(int width_px, int height_px, const std::string& text, const TextScreenStyle& style) {
  Rgba8Frame frame = black_frame(width_px, height_px);
  const std::string font = style.font_path.empty() ? find_font_path() : style.font_path;
  const int margin_x = static_cast<int>(std::lround(style.margin_fraction * width_px));
  const int margin_y = static_cast<int>(std::lround(style.margin_fraction * height_px));
  const int max_width = std::max(1, width_px - 2 * margin_x);
  const int max_height = std::max(1, height_px - 2 * margin_y);

  // The largest size up to the nominal one at which the wrapped block fits the height.
  std::vector<std::string> lines;
  int font_px = font_px_for(style, height_px);
  int ascent = 0, descent = 0, pitch = 0, block_height = 0;
  for (;; --font_px) {
    lines = wrap_text(text, max_width, font_px, font);
    const OIIO::ROI extent = OIIO::ImageBufAlgo::text_size("\xC3\x81g", font_px, font);  // "Ág": tallest and deepest
    if (!extent.defined()) throw std::runtime_error("text screen: cannot use font " + font);
    ascent = -extent.ybegin;
    descent = extent.yend;
    pitch = static_cast<int>(std::lround(style.line_spacing * font_px));
    block_height = static_cast<int>(lines.size() - 1) * pitch + ascent + descent;
    if (block_height <= max_height || font_px <= kSmallestFontPx) break;
  }

  OIIO::ImageSpec spec(width_px, height_px, 4, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf canvas(spec, frame.rgba.data());  // draws straight into the frame
  const float grey = static_cast<float>(style.grey) / 255.0f;
  const float colour[4] = {grey, grey, grey, 1.0f};
  const int top = (height_px - block_height) / 2;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const int baseline = top + ascent + static_cast<int>(i) * pitch;
    // A frame too small for the text even at the smallest size: lines wholly outside it are not
    // drawn (OpenImageIO asserts on text that misses the image entirely).
    if (baseline - ascent < 0 || baseline + descent > height_px) continue;
    if (!OIIO::ImageBufAlgo::render_text(canvas, width_px / 2, baseline, lines[i], font_px, font, colour,
                                         OIIO::ImageBufAlgo::TextAlignX::Center,
                                         OIIO::ImageBufAlgo::TextAlignY::Baseline)) {
      throw std::runtime_error("text screen: cannot draw text: " + canvas.geterror());
    }
  }
  return frame;
}

Rgba8Frame fixation_cross_frame(int width_px, int height_px, const TextScreenStyle& style) {
  Rgba8Frame frame = black_frame(width_px, height_px);
  const int arm = std::max(2, static_cast<int>(std::lround(0.015 * height_px)));
  const int stroke = std::max(1, static_cast<int>(std::lround(height_px / 360.0)));
  const int cx = width_px / 2, cy = height_px / 2;
  auto fill = [&](int x0, int y0, int x1, int y1) {  // inclusive-exclusive, clipped
    for (int y = std::max(0, y0); y < std::min(height_px, y1); ++y) {
      for (int x = std::max(0, x0); x < std::min(width_px, x1); ++x) {
        uint8_t* p =
            frame.rgba.data() + (static_cast<size_t>(y) * static_cast<size_t>(width_px) + static_cast<size_t>(x)) * 4;
        p[0] = p[1] = p[2] = style.grey;
      }
    }
  };
  fill(cx - arm, cy - stroke / 2, cx + arm + 1, cy - stroke / 2 + stroke);  // horizontal
  fill(cx - stroke / 2, cy - arm, cx - stroke / 2 + stroke, cy + arm + 1);  // vertical
  return frame;
}

Rgba8Frame validation_target_frame(int width_px, int height_px, double x_px, double y_px, double radius_px,
                                   const TextScreenStyle& style) {
  Rgba8Frame frame = black_frame(width_px, height_px);
  const double dot_px = std::max(1.0, 0.25 * radius_px);
  const int x0 = std::max(0, static_cast<int>(std::floor(x_px - radius_px)));
  const int x1 = std::min(width_px, static_cast<int>(std::ceil(x_px + radius_px)) + 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(y_px - radius_px)));
  const int y1 = std::min(height_px, static_cast<int>(std::ceil(y_px + radius_px)) + 1);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const double distance = std::hypot(x + 0.5 - x_px, y + 0.5 - y_px);
      if (distance > radius_px || distance <= dot_px) continue;
      uint8_t* p =
          frame.rgba.data() + (static_cast<size_t>(y) * static_cast<size_t>(width_px) + static_cast<size_t>(x)) * 4;
      p[0] = p[1] = p[2] = style.grey;
    }
  }
  return frame;
}

}  // namespace fovlab
