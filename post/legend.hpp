#pragma once
// Legends: entries (a marker in a colour and a label) in a grid filled row
// by row, every cell as wide as the widest entry, with as many columns as fit
// the width given, so that any number of entries is listed. Pictures place
// the legend in a band of its own, outside the plot and below the title.
#include <string>
#include <vector>

#include "branch_style.hpp"
#include "canvas.hpp"

namespace pd::post {

struct LegendEntry {
  std::string label;
  BranchStyle style;
};

struct Legend {
  std::vector<LegendEntry> entries;
  int columns = 1, rows = 0, cell_width = 0;
  static constexpr int row_height = 18;
  int width() const { return entries.empty() ? 0 : columns * cell_width; }
  int height() const { return rows * row_height; }
};

Legend make_legend(std::vector<LegendEntry> entries, int max_width);

// Entries "b0", "b1", ... for the given branches, in increasing branch number, each once.
std::vector<LegendEntry> branch_legend_entries(std::vector<int> branches);

// Draws the legend with its top-left corner at (left, top).
void draw_legend(Canvas& canvas, const Legend& legend, int left, int top);

}  // namespace pd::post
