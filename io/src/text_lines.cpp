#include "text_lines.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "radar_ndt/io/io_error.h"

namespace radar_ndt {
namespace detail {

bool isBlank(const std::string& line) {
  return line.find_first_not_of(" \t\r") == std::string::npos;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
    while (!cell.empty() && cell.front() == ' ') cell.erase(cell.begin());
    out.push_back(cell);
  }
  return out;
}

std::int64_t parseInt64(const std::string& path, std::size_t line, const std::string& token, const char* what) {
  try {
    std::size_t used = 0;
    const long long v = std::stoll(token, &used);
    if (used != token.size()) throw std::invalid_argument(token);
    return v;
  } catch (const std::exception&) {
    throw IoError(path, line, std::string("cannot parse ") + what + " '" + token + "' as an integer");
  }
}

double parseFinite(const std::string& path, std::size_t line, const std::string& token, const char* what) {
  double v = 0.0;
  try {
    std::size_t used = 0;
    v = std::stod(token, &used);
    if (used != token.size()) throw std::invalid_argument(token);
  } catch (const std::exception&) {
    throw IoError(path, line, std::string("cannot parse ") + what + " '" + token + "' as a number");
  }
  if (!std::isfinite(v)) throw IoError(path, line, std::string(what) + " is not finite");
  return v;
}

}  // namespace detail
}  // namespace radar_ndt
