#include "core/toml_guard.h"

#include <cstdint>
#include <vector>

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

namespace {

// A scanner of TOML text that sees only what builds depth: table headers, dotted keys, arrays and
// inline tables; strings and comments are stepped over, everything else is left to toml++.
class NestingScanner {
 public:
  NestingScanner(const std::string& text, const std::string& path, int max_depth)
      : text_(text), path_(path), max_depth_(max_depth) {}

  void run() {
    if (text_.compare(0, 3, "\xEF\xBB\xBF") == 0) i_ = 3;  // a byte-order mark, skipped by toml++ too
    while (i_ < text_.size()) {
      const char c = text_[i_];
      if (c == '\n') {
        ++line_;
        ++i_;
        if (frames_.empty()) start_line();  // a top-level value ends at its line's end
        continue;
      }
      if (c == '#') {
        while (i_ < text_.size() && text_[i_] != '\n') ++i_;
        continue;
      }
      if (c == '"' || c == '\'') {
        skip_string();
        continue;
      }
      ++i_;
      switch (mode_) {
        case Mode::key:
          key_character(c);
          break;
        case Mode::header:
          header_character(c);
          break;
        case Mode::value:
          value_character(c);
          break;
        case Mode::rest_of_line:
          break;
      }
    }
  }

 private:
  enum class Mode { key, header, value, rest_of_line };
  struct Frame {
    bool inline_table;    // else an array
    int depth;            // of the array or table itself
    int value_depth = 0;  // inline table: depth of the value being read (its key's last part)
  };

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(line_) + ": " + what + " nested deeper than " +
                     std::to_string(max_depth_) + " levels: expected at most " + std::to_string(max_depth_) +
                     " (table header parts, dotted key parts, arrays and inline tables together)");
  }

  void start_line() {
    mode_ = Mode::key;
    key_parts_ = 1;
  }

  int key_base() const { return frames_.empty() ? header_depth_ : frames_.back().depth; }

  int value_depth() const {
    if (frames_.empty()) return top_value_depth_;
    return frames_.back().inline_table ? frames_.back().value_depth : frames_.back().depth;
  }

  void key_character(char c) {
    if (c == '[' && frames_.empty()) {  // a table header, [a.b] or [[a.b]]
      mode_ = Mode::header;
      key_parts_ = 1;
      header_extra_ = 0;
      if (i_ < text_.size() && text_[i_] == '[') {
        header_extra_ = 1;  // an array of tables: one level more
        ++i_;
      }
    } else if (c == '.') {
      if (key_base() + ++key_parts_ > max_depth_) fail("dotted key");
    } else if (c == '=') {
      const int depth = key_base() + key_parts_;
      if (frames_.empty()) top_value_depth_ = depth;
      else frames_.back().value_depth = depth;
      mode_ = Mode::value;
    } else if (c == '}' && !frames_.empty() && frames_.back().inline_table) {  // {} or a trailing comma
      frames_.pop_back();
      mode_ = Mode::value;
    }
  }

  void header_character(char c) {
    if (c == '.') {
      if (++key_parts_ + header_extra_ > max_depth_) fail("table header");
    } else if (c == ']') {
      header_depth_ = key_parts_ + header_extra_;
      if (header_extra_ && i_ < text_.size() && text_[i_] == ']') ++i_;
      mode_ = Mode::rest_of_line;
    }
  }

  void value_character(char c) {
    if (c == '[' || c == '{') {
      const int depth = value_depth() + 1;
      if (depth > max_depth_) fail(c == '[' ? "array" : "inline table");
      frames_.push_back({c == '{', depth});
      if (c == '{') {
        mode_ = Mode::key;
        key_parts_ = 1;
      }
    } else if ((c == ']' || c == '}') && !frames_.empty() && frames_.back().inline_table == (c == '}')) {
      frames_.pop_back();
    } else if (c == ',' && !frames_.empty() && frames_.back().inline_table) {
      mode_ = Mode::key;
      key_parts_ = 1;
    }
  }

  // Steps over a basic or literal string, single- or multi-line, counting its lines. An unclosed
  // single-line string ends at its line's end (toml++ reports it).
  void skip_string() {
    const char quote = text_[i_];
    const bool multi_line = text_.compare(i_, 3, std::string(3, quote)) == 0;
    i_ += multi_line ? 3 : 1;
    while (i_ < text_.size()) {
      const char c = text_[i_];
      if (c == '\n') {
        if (!multi_line) return;
        ++line_;
      } else if (c == '\\' && quote == '"') {
        if (i_ + 1 < text_.size() && text_[i_ + 1] == '\n') ++line_;
        i_ += 2;
        continue;
      } else if (c == quote) {
        if (!multi_line) {
          ++i_;
          return;
        }
        if (text_.compare(i_, 3, std::string(3, quote)) == 0) {
          i_ += 3;
          for (int extra = 0; extra < 2 && i_ < text_.size() && text_[i_] == quote; ++extra) ++i_;  // """a""""" is a""
          return;
        }
      }
      ++i_;
    }
  }

  const std::string& text_;
  const std::string& path_;
  const int max_depth_;
  size_t i_ = 0;
  int line_ = 1;
  Mode mode_ = Mode::key;
  int key_parts_ = 1;
  int header_extra_ = 0;
  int header_depth_ = 0;       // of the current [table] (0 for the root table)
  int top_value_depth_ = 0;    // of the top-level key/value being read
  std::vector<Frame> frames_;  // open arrays and inline tables, innermost last
};

}  // namespace

void check_toml_nesting(const std::string& text, const std::string& path, int max_depth) {
  NestingScanner(text, path, max_depth).run();
}

}  // namespace fovlab
