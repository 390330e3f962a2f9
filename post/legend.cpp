#include "legend.hpp"

#include <algorithm>

namespace pd::post {

Legend make_legend(std::vector<LegendEntry> entries, int max_width) {
  Legend g;
  g.entries = std::move(entries);
  if (g.entries.empty()) return g;
  int widest = 0;
  for (const auto& e : g.entries) widest = std::max(widest, Canvas::text_width(e.label));
  // Marker 12 px, 4 px to the label, 16 px to the next cell.
  g.cell_width = 32 + widest;
  g.columns = std::clamp(max_width / g.cell_width, 1, static_cast<int>(g.entries.size()));
  g.rows = (static_cast<int>(g.entries.size()) + g.columns - 1) / g.columns;
  return g;
}

std::vector<LegendEntry> branch_legend_entries(std::vector<int> branches) {
  std::sort(branches.begin(), branches.end());
  branches.erase(std::unique(branches.begin(), branches.end()), branches.end());
  std::vector<LegendEntry> entries;
  for (int b : branches) entries.push_back({"b" + std::to_string(b), branch_style(b)});
  return entries;
}

void draw_legend(Canvas& c, const Legend& g, int left, int top) {
  for (std::size_t i = 0; i < g.entries.size(); ++i) {
    const int x = left + static_cast<int>(i) % g.columns * g.cell_width;
    const int y = top + static_cast<int>(i) / g.columns * Legend::row_height;
    const auto& e = g.entries[i];
    // A black rim keeps light colours apart from the white ground.
    draw_marker(c, x + 6, y + 7, e.style.marker, 7, black, true);
    draw_marker(c, x + 6, y + 7, e.style.marker, 5, e.style.color, true);
    c.text(x + 16, y, e.label, black);
  }
}

}  // namespace pd::post
