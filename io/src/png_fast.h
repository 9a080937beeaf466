#pragma once
// Internal to RadarNDT::io: the fast decoder for the PNGs polar scans are (8-bit grey, not
// interlaced): libdeflate inflates the image data in one call and PNG's five row filters are undone
// here. It takes only files it can decode exactly as libpng does; the caller hands every other file
// (other layouts, bad CRCs, truncated or malformed streams, anything unusual) to libpng, whose
// answer, the pixels or the error, is the file's.
#include <cstdint>
#include <string>
#include <vector>

namespace radar_ndt {
namespace detail {

/// Decodes `data` (a whole PNG file) into `pixels` (width × height, row-major) when it is a
/// well-formed 8-bit grey, non-interlaced PNG; false (outputs unspecified) otherwise. `max_pixels`
/// and `max_inflation` bound what a header may declare (the caller's refusals; a file beyond them
/// goes to the caller's own checks).
bool decodeCanonicalGrayPng(const std::string& data, std::size_t max_pixels, std::size_t max_inflation, int& width,
                            int& height, std::vector<std::uint8_t>& pixels);

/// Undoes one PNG row filter (type 0–4, bytes per pixel 1) of `width` bytes: `filtered` is the row
/// after its filter-type byte, `previous` the previous decoded row (nullptr for the first row),
/// `out` the decoded row. False for an unknown filter type.
bool unfilterRow(int type, const std::uint8_t* filtered, const std::uint8_t* previous, std::uint8_t* out,
                 std::size_t width);

}  // namespace detail
}  // namespace radar_ndt
