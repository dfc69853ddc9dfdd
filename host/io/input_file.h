// A user's input file (a scene, a mesh) read whole and bounded: only a regular file (a device such
// as /dev/zero or /dev/urandom, a pipe or a directory is refused, behind a symlink too), and at most
// the input limit, PERIFRAC_MAX_INPUT_MB megabytes (default 1024): a larger file, or one that grows
// past the limit while it is read, is refused instead of filling the memory.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace pd {

// The limit in bytes: PERIFRAC_MAX_INPUT_MB, else 1024 MB. Throws std::invalid_argument for a value
// that is not a whole number of MB from 1 up.
size_t input_limit_bytes();

// The file's bytes; or nothing, with `why` saying what is wrong ("not a regular file (a character
// device)", the system's reason, "larger than the input limit ...").
std::optional<std::string> read_input_file(const std::string& path, std::string& why);

// Whether `path` is a regular file within the input limit, by its metadata only (for inputs that a
// library reads itself, such as the renderer's environment map); else `why` says what is wrong.
bool is_bounded_input(const std::string& path, std::string& why);

// A file a run wrote and reads back (a checkpoint, which may exceed the input limit): a regular
// file only, read up to the size it had when opened (a file that grows meanwhile is refused).
std::optional<std::string> read_output_file(const std::string& path, std::string& why);

}  // namespace pd
