#pragma once
#include <stdexcept>
#include <string>

namespace radar_ndt {

/// Thrown by every reader and writer. The message names the file (and line, where there is one)
/// and what is wrong with it, e.g. "traj.txt:12: expected 12 numbers, found 11".
class IoError : public std::runtime_error {
 public:
  IoError(const std::string& file, const std::string& what) : std::runtime_error(file + ": " + what), file_(file) {}
  IoError(const std::string& file, std::size_t line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what), file_(file), line_(line) {}
  const std::string& file() const noexcept { return file_; }
  /// 1-based line number, 0 when the problem is not tied to a line.
  std::size_t line() const noexcept { return line_; }

 private:
  std::string file_;
  std::size_t line_ = 0;
};

}  // namespace radar_ndt
