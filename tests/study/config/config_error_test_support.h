#pragma once
// Shared by the config tests: where a key sits in a config's text, and the check that a config is
// refused in one line "PATH:LINE: KEY: ..." (docs/config.md, "Errors").
#include <algorithm>
#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"

namespace fovlab::test {

// 1-based line of the n-th (from 1) occurrence of `needle` in `text`; -1 (and a failure) if absent.
inline int line_of(const std::string& text, const std::string& needle, int occurrence = 1) {
  size_t at = std::string::npos;
  size_t from = 0;
  for (int i = 0; i < occurrence; ++i) {
    at = text.find(needle, from);
    if (at == std::string::npos) {
      ADD_FAILURE() << "not found: " << needle;
      return -1;
    }
    from = at + 1;
  }
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// The InputError parsing `text` (as the file `path`) gives; "" and a failure when it gives none.
inline std::string config_error_of(const std::string& text, const std::string& path) {
  try {
    parse_study_config_text(text, path, renderer_scene_catalog());
  } catch (const InputError& error) {
    return error.what();
  } catch (const std::exception& error) {
    ADD_FAILURE() << "not an InputError: " << error.what();
    return "";
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

// The refusal is one line that starts "PATH:LINE: KEY: " and contains `fragment`; returns it.
inline std::string expect_config_error(const std::string& text, const std::string& path, int line, const std::string& key,
                                const std::string& fragment) {
  const std::string message = config_error_of(text, path);
  SCOPED_TRACE(message);
  EXPECT_EQ(message.find('\n'), std::string::npos) << "more than one line";
  const std::string prefix = path + ":" + std::to_string(line) + ": " + key + ": ";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << "expected the prefix \"" << prefix << "\"";
  EXPECT_NE(message.find(fragment), std::string::npos) << "expected to contain \"" << fragment << "\"";
  return message;
}

}  // namespace fovlab::test
