#pragma once
// ddt::Error — the one exception type the library throws for bad input or
// failed I/O. Its message is a single line meant for the user.

#include <stdexcept>
#include <string>

namespace ddt {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace ddt
