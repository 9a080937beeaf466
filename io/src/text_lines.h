#pragma once
// Internal to RadarNDT::io: the one line reader every text reader uses (trajectories, Oxford's
// index and ground truth, RADIATE's frame times), and the token parsers they share. Errors are
// IoErrors naming the file and the line.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "radar_ndt/io/io_error.h"
#include "read_file.h"

namespace radar_ndt {
namespace detail {

/// Calls `fn(line_no, line)` for each line of `text`, numbered from 1: lines end at '\n', a
/// trailing '\r' is dropped, a last line without '\n' counts, nothing follows a final '\n'. Blank
/// and comment lines are passed on: each format decides. `fn` returns false to stop.
template <typename Fn>
void forEachLine(const std::string& text, Fn&& fn) {
  std::size_t pos = 0, line_no = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line = text.substr(pos, eol - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = eol + 1;
    if (!fn(++line_no, line)) return;
  }
}

/// True when the line holds nothing but spaces and tabs.
bool isBlank(const std::string& line);

/// An index file's entries, one a line (blank lines skipped): `parse(line_no, line, so_far)` gives
/// the line's entry or throws IoError. Without `skipped` the first bad line throws; with it, a bad
/// line is left out and its error kept there, so a sequence with a few bad index lines can run.
template <typename T, typename Parse>
std::vector<T> readIndexLines(const std::string& path, std::vector<IoError>* skipped, Parse&& parse) {
  std::vector<T> out;
  forEachLine(readWholeFile(path), [&](std::size_t n, const std::string& line) {
    if (isBlank(line)) return true;
    try {
      out.push_back(parse(n, line, out));
    } catch (const IoError& e) {
      if (!skipped) throw;
      skipped->push_back(e);
    }
    return true;
  });
  return out;
}
/// The comma-separated cells of a CSV line, each without surrounding spaces.
std::vector<std::string> splitCsv(const std::string& line);
/// The whole token as an integer or a finite number; IoError naming `what`, the file and line
/// otherwise.
std::int64_t parseInt64(const std::string& path, std::size_t line, const std::string& token, const char* what);
double parseFinite(const std::string& path, std::size_t line, const std::string& token, const char* what);

}  // namespace detail
}  // namespace radar_ndt
