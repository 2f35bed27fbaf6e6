#pragma once
// The last line of Teem's nrrd error stack (biff), cleared: the one-line
// reason every Teem caller (NRRD I/O, resampling, smoothing) reports.

#include <teem/nrrd.h>

#include <cstdlib>
#include <string>

namespace ddt {

inline std::string teem_error() {
  char* err = biffGetDone(NRRD);
  std::string s = err ? err : "unknown Teem error";
  std::free(err);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  const auto nl = s.rfind('\n');
  return nl == std::string::npos ? s : s.substr(nl + 1);
}

}  // namespace ddt
