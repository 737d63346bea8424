#include "analysis/model/program_files.h"

#include <system_error>

namespace ishibashi {

const std::filesystem::path& program_files_root() {
  static const std::filesystem::path root = [] {
    std::error_code error;
    const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
    // The installed layout's share folder, named as the install rules name it (CMakeLists.txt).
    const std::filesystem::path installed = program.parent_path().parent_path() / "share" / "ishibashi";
    if (!error && std::filesystem::is_directory(installed / "analysis" / "report", error)) return installed;
    return std::filesystem::path(ISHIBASHI_SOURCE_DIR);
  }();
  return root;
}

std::filesystem::path program_file(const std::string& relative) { return program_files_root() / relative; }

}  // namespace ishibashi
