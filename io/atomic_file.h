// Writes that never leave a half-written file behind: write to a temporary file in the
// same folder, then rename it over the target (atomic on POSIX file systems).
#pragma once
#include <filesystem>
#include <functional>
#include <string>

namespace ishibashi {

// Calls write(temporary_path) and renames the result to `target`. When write throws (a
// full disk) the temporary file is removed and the exception passed on; a failed rename
// throws std::runtime_error naming the file.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write);

// Atomic write of a whole text (or binary) file; the error says why (errno's text).
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

}  // namespace ishibashi
