// The files the program ships with: the report scripts (analysis/report/), the study's
// scenarios, the models and the ground motions. An installed program (`cmake --install`)
// reads them from PREFIX/share/ishibashi beside PREFIX/bin/ishibashi, so that it runs
// anywhere and its build and source trees can go; a program run where it was built reads
// them from the source tree it was built from.
#pragma once
#include <filesystem>
#include <string>

namespace ishibashi {

// PREFIX/share/ishibashi when the program runs from PREFIX/bin and that folder holds the
// report scripts, else the source tree's root.
const std::filesystem::path& program_files_root();
// `relative` (e.g. "analysis/report/report.py") under program_files_root().
std::filesystem::path program_file(const std::string& relative);

}  // namespace ishibashi
