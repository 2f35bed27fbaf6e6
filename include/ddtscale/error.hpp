#pragma once
// ddt::Error — the one exception type the library throws for bad input or
// failed I/O. Its message is a single line meant for the user.

#include <stdexcept>
#include <string>

namespace ddt {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An input that cannot be read or an output that cannot be written (the
// Python module raises it as OSError, the other errors as ValueError).
struct FileError : Error {
  using Error::Error;
};

}  // namespace ddt
