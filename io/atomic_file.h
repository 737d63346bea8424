// Writes that never leave a half-written file behind: write to a temporary file in the
// same folder, then rename it over the target (atomic on POSIX file systems).
#pragma once
#include <filesystem>
#include <functional>
#include <string>

namespace ishibashi {

// Calls write(temporary_path) and renames the result to `target`. Throws
// std::runtime_error naming the file when the write or the rename fails.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write);

// Atomic write of a whole text file.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

}  // namespace ishibashi
