#pragma once
// A 5 x 7 pixel bitmap font (plus a descender row) for picture labels: digits, letters and a few
// symbols (printable ASCII; unknown characters draw as a box).
#include <array>
#include <cstdint>

namespace pd::post {

inline constexpr int glyph_width = 5;
inline constexpr int glyph_height = 8;  // 7 rows + a descender row

// Eight rows, top first; bit 4 of each row is the left-most pixel.
std::array<std::uint8_t, glyph_height> glyph(char c);

}  // namespace pd::post
