// Running the program from a test, as a user would: its output and exit status, and the
// files it wrote.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

namespace ishibashi::test {

inline const std::filesystem::path kRoot = ISHIBASHI_SOURCE_DIR;
// The program under test: ISHIBASHI_PROGRAM, which ctest sets to the program of the tests'
// own build (a sanitizer build links the Release build's test objects, which name the
// Release program: tests/CMakeLists.txt), else the program built beside this test.
#ifdef ISHIBASHI_BINARY
inline std::string program() {
  const char* set = std::getenv("ISHIBASHI_PROGRAM");
  return set ? set : ISHIBASHI_BINARY;
}
#endif
// This test process's own temporary folder (test_main.cpp).
inline std::filesystem::path tmp_dir() { return std::filesystem::temp_directory_path(); }

// A box from `at` to `at` + `size` (m), as an OFF file that a model's [import] reads.
inline std::filesystem::path box_off_file(const std::filesystem::path& file, const double (&at)[3], const double (&size)[3]) {
  std::ofstream out(file);
  out << "OFF\n8 6 0\n";
  for (int k = 0; k < 8; ++k)
    out << at[0] + (k & 1 ? size[0] : 0) << ' ' << at[1] + (k & 2 ? size[1] : 0) << ' ' << at[2] + (k & 4 ? size[2] : 0) << '\n';
  out << "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
  return file;
}

// Prefix of a command run on two MPI ranks (as root in CI's containers; more ranks than
// cores allowed).
inline const std::string kMpirunTwoRanks =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 2 ";

// stdout and stderr of a shell command; *status its exit status (as pclose returns it).
inline std::string run_command(const std::string& command, int* status) {
  std::string output;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen((command + " 2>&1").c_str(), "r"), pclose);
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe.get())) output += buffer;
  *status = pclose(pipe.release());
  return output;
}

inline std::string text_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// A run folder's state hash as summary.json gives it ("state_hash": "..."); empty when it
// has none: two runs ended in the same state when these are equal and not empty.
inline std::string state_hash_of(const std::filesystem::path& run) {
  const std::string summary = text_of(run / "summary.json");
  const std::size_t at = summary.find("\"state_hash\"");
  return at == std::string::npos ? std::string() : summary.substr(at, summary.find('\n', at) - at);
}

}  // namespace ishibashi::test
