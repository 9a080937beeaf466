#pragma once
// printf into a std::string: the reports' fixed-format lines (run_report.cpp, inertial_report.cpp).

#include <cstdarg>
#include <cstdio>
#include <string>

namespace radar_ndt {
namespace detail {

/// The formatted text, cut at 1023 characters (the reports' lines are far shorter).
inline std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string format(const char* fmt, ...) {
  char buffer[1024];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  return buffer;
}

}  // namespace detail
}  // namespace radar_ndt
