#include "protocols/config/toml_guard.h"

#include <cstdint>

#include "core/input_error.h"

namespace fovlab {
namespace {

struct Range {
  char32_t first, last;
};
// The hazard code points (see the header), and U+3000 in the middle of the second range is safe.
constexpr Range hazard_ranges[] = {{0xA1, 0x499}, {0x2C5E, 0x2FFF}, {0x3001, 0x3057}, {0xFB26, 0xFEFE}};
constexpr char32_t placeholder_base = 0xF0000;
constexpr char32_t placeholder_end = 0xF0000 + 0x10000;  // the block of placeholders (and a margin)

// Index of a hazard among all hazards, or -1.
int hazard_index(char32_t c) {
  int offset = 0;
  for (const Range& range : hazard_ranges) {
    if (c >= range.first && c <= range.last) return offset + static_cast<int>(c - range.first);
    offset += static_cast<int>(range.last - range.first + 1);
  }
  return -1;
}

char32_t hazard_at(int index) {
  for (const Range& range : hazard_ranges) {
    const int size = static_cast<int>(range.last - range.first + 1);
    if (index < size) return range.first + static_cast<char32_t>(index);
    index -= size;
  }
  return 0;
}

// Decodes the well-formed UTF-8 sequence at i, or returns false (the byte is then copied as is:
// toml++ reports malformed UTF-8 itself).
bool decode(const std::string& text, size_t i, char32_t& c, size_t& length) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  length = (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xE ? 3 : (lead >> 3) == 0x1E ? 4 : 0;
  if (length == 0 || i + length > text.size()) return false;
  c = lead & (0x7F >> length);
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return false;
    c = (c << 6) | (byte(i + k) & 0x3F);
  }
  return true;
}

void encode(char32_t c, std::string& out) {
  if (c < 0x80) {
    out += static_cast<char>(c);
  } else if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (c >> 18));
    out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

// Copies text, replacing each decoded code point by map(c) (or keeping it when map returns 0).
template <typename Map>
std::string transcode(const std::string& text, Map map) {
  std::string out;
  out.reserve(text.size() + text.size() / 4);
  for (size_t i = 0; i < text.size();) {
    char32_t c = 0;
    size_t length = 0;
    if (static_cast<unsigned char>(text[i]) >= 0x80 && decode(text, i, c, length)) {
      const char32_t mapped = map(c);
      if (mapped) encode(mapped, out);
      else out.append(text, i, length);
      i += length;
    } else {
      out += text[i++];
    }
  }
  return out;
}

}  // namespace

std::string shield_toml_hazards(const std::string& text, const std::string& path) {
  int line = 1;
  size_t line_start_scan = 0;
  return transcode(text, [&](char32_t c) -> char32_t {
    if (c >= placeholder_base && c < placeholder_end) {
      for (; line_start_scan < text.size(); ++line_start_scan) {  // the line of the first such code point
        char32_t found = 0;
        size_t length = 0;
        if (text[line_start_scan] == '\n') ++line;
        if (decode(text, line_start_scan, found, length) && found == c) break;
      }
      throw InputError(path + ":" + std::to_string(line) +
                       ": code points U+F0000-U+FFFFF (private use) are not accepted in a config");
    }
    const int index = hazard_index(c);
    return index < 0 ? 0 : placeholder_base + static_cast<char32_t>(index);
  });
}

std::string unshield_toml_hazards(const std::string& text) {
  return transcode(text, [](char32_t c) -> char32_t {
    return c >= placeholder_base && c < placeholder_end ? hazard_at(static_cast<int>(c - placeholder_base)) : 0;
  });
}

}  // namespace fovlab
