// The main() of every test program: each test process gets its own temporary folder.
// ctest runs tests in parallel (-j), one process per test, and many tests write scratch
// files under fixed names (a scenario, a model, an output folder); in a shared /tmp two of
// them could overwrite each other's files (a 0.2 s run reading the 20 s scenario of the
// test beside it). TMPDIR is what std::filesystem::temp_directory_path() returns, here
// and in the programs the tests start.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <string>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  std::string pattern = (std::filesystem::temp_directory_path() / "ishibashi_test_XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) {
    std::perror("test main: cannot make a temporary folder");
    return 1;
  }
  setenv("TMPDIR", pattern.c_str(), 1);
  const int status = RUN_ALL_TESTS();
  std::error_code ignored;
  std::filesystem::remove_all(pattern, ignored);
  return status;
}
