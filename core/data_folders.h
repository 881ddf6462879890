#pragma once
// Where fovlab's own data lives (the built-in scenes and volumes under stimuli/), found at run time
// rather than compiled in: the product binary holds no path of the machine it was built on.
#include <filesystem>

namespace fovlab {

// The stimuli/ folder: the first of <dir>/stimuli, <dir>/../stimuli, <dir>/../../stimuli and
// <dir>/../share/fovlab/stimuli that exists, <dir> being the running program's folder (so
// build/release/fovlab finds the checkout's stimuli/, an installed bin/fovlab its share/ folder);
// "stimuli" under the working directory when none does.
std::filesystem::path stimuli_directory();

// `variable`'s value when the environment sets it to a non-empty path, else stimuli_directory()/`sub`.
std::filesystem::path stimuli_subdirectory(const char* variable, const char* sub);

}  // namespace fovlab
