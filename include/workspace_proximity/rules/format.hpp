#pragma once
/// One number into a printf format, for status lines and log messages (off the hot path).

#include <cstdio>
#include <string>

namespace workspace_proximity {

/// `fmt` with one double conversion, e.g. format("no data for %.2f s", 1.234).
inline std::string format(const char* fmt, double value) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
}

}  // namespace workspace_proximity
