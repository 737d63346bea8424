// Bad input from a user's file or command line: the message names the file (and the line
// or key) and says what would be right. Every reader and analysis throws it; the commands
// print it and exit with status 2.
#pragma once
#include <stdexcept>

namespace ishibashi {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace ishibashi
