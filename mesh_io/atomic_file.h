// Atomic output files (SPEC section 8): write to a uniquely named temporary
// file in the target's folder, rename it over the target only when complete.
// A crash or error never leaves a partial file under the target's name.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "mapping/error.h"

namespace texbake {

// Calls write(temp_path) with a fresh temporary path in target's folder whose
// name ends with target's extension (so extension-sniffing writers such as
// OpenImageIO pick the right format). On success renames temp over target; on
// failure (write returns an error, throws, or the rename fails) removes the
// temporary file and returns the error. Errors name the target.
Status write_atomically(const std::filesystem::path& target,
                        const std::function<Status(const std::filesystem::path& temp)>& write);

// Checks, before any long work, that target's folder exists and is writable.
Status check_writable(const std::filesystem::path& target);

}  // namespace texbake
