#pragma once
// A shield in front of toml++ 3.3.0 (Debian 12): its is_non_ascii_horizontal_whitespace() reaches
// TOML_UNREACHABLE (undefined behaviour) for code points in U+00A1-U+0499, U+2C5E-U+3057 (but
// U+3000) and U+FB26-U+FEFE whenever the parser asks whether one is whitespace, which it does in
// bare keys, values and multi-line strings (upstream marzer/tomlplusplus #295, fixed by PR #305,
// not in Debian 12; found by fuzzing). Such characters are legitimate inside strings (instructions
// in French, Greek, Cyrillic...), so instead of rejecting them, every one is swapped for a code
// point of Supplementary Private Use Area-A (U+F0000 + its index), which toml++ classifies without
// reaching the bad branch, and swapped back in every string read from the parsed table. Outside
// strings they were never valid TOML, and toml++ reports the placeholder there as it would the
// original. Text that already holds code points of that private range is rejected.
#include <string>

namespace fovlab {

// The text with hazards swapped for placeholders. Throws InputError "path:LINE: ..." for a code
// point of the placeholder range in the input.
std::string shield_toml_hazards(const std::string& text, const std::string& path);

// The inverse, for strings read from the parsed table (and messages that quote them).
std::string unshield_toml_hazards(const std::string& text);

// toml++ parses and frees nested values recursively and bounds only arrays and inline tables (256
// levels), not dotted keys: a key of 40,000 parts (`a.a.a...= 1`, in a header or a key/value line)
// overflows the stack. Before toml++ sees the text, check_toml_nesting measures every value's
// depth: the parts of its table header, plus the parts of the dotted keys leading to it, plus the
// arrays and inline tables around it (`[a.b]` then `c.d = [{e = 1}]`: e is at depth 2 + 2 + 2 + 1).
// Throws InputError "path:LINE: ..." at the first point deeper than max_depth. Strings and comments
// are skipped as TOML defines them; anything malformed is left to toml++ to report.
void check_toml_nesting(const std::string& text, const std::string& path, int max_depth);

}  // namespace fovlab
