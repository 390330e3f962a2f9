#include "small_free_cells.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "families.hpp"
#include "resource_estimate.hpp"
#include "units.hpp"

namespace pd {

namespace {

constexpr double small_ratio = 0.5;  // a cell below half its target size is small

std::string mm_text(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g mm", metres * 1e3);
  return text;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

bool SmallFreeCells::forced() const {
  return small > 0 && (median_ratio < small_ratio || small_family > 2 * usual_family);
}

SmallFreeCells find_small_free_cells(const ParticleSet& p, const std::vector<double>& family_sizes,
                                     double box_spacing) {
  SmallFreeCells s;
  const double m = p.horizon_nominal / p.spacing;
  const auto target = [&](std::size_t i) {
    return box_spacing > 0 && p.region[i] == static_cast<std::uint8_t>(Region::box_free_mesh) ? box_spacing
                                                                                              : p.horizon[i] / m;
  };
  s.usual_family = static_cast<double>(interior_family_size(m, p.quadrature));
  std::vector<double> ratios, small_sizes;
  std::vector<std::size_t> small_cells;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.region[i] == static_cast<std::uint8_t>(Region::uniform_square)) continue;
    const double ratio = p.cell_size[i] / target(i);
    ratios.push_back(ratio);
    if (ratio < s.smallest_ratio) s.smallest_ratio = ratio, s.smallest_at = {p.x[i], p.y[i]};
    if (ratio >= small_ratio) continue;
    small_sizes.push_back(p.cell_size[i]);
    small_cells.push_back(i);
    s.small_family += family_sizes[i];
  }
  s.free_cells = ratios.size();
  s.small = small_cells.size();
  if (s.free_cells == 0) return s;
  s.median_ratio = median(ratios);
  if (s.small == 0) return s;
  s.small_family /= static_cast<double>(s.small);
  s.median_small_size = median(small_sizes);
  // The target of the small cell closest to the median size (one box or
  // grading level in practice).
  std::size_t typical = small_cells.front();
  for (std::size_t i : small_cells)
    if (std::fabs(p.cell_size[i] - s.median_small_size) < std::fabs(p.cell_size[typical] - s.median_small_size))
      typical = i;
  s.target_size = target(typical);
  return s;
}

std::vector<std::string> small_free_cells_remedies(const SmallFreeCells& s, const ParticleSet& p,
                                                   double box_spacing, double graded_fine) {
  const double size = s.median_small_size;
  std::vector<std::string> remedies;
  char text[96];
  if (p.grid == GridKind::nbnug) {
    // The box spacings pd-mesh offers: dx / 2^k, k = 0 ... 6; the one
    // nearest the cells' size (within a factor of sqrt 2).
    double dxb = p.spacing;
    for (int k = 0; k < 6 && dxb > size * std::sqrt(2.0); ++k) dxb /= 2;
    if (box_spacing <= 0 || dxb < box_spacing * (1 - 1e-9)) {
      std::snprintf(text, sizeof text, "--box-spacing %.6gmm (the boxes' horizons then follow their cells)",
                    dxb * 1e3);
      remedies.push_back(text);
    }
  } else if (p.grid == GridKind::free && (graded_fine <= 0 || size < graded_fine * (1 - 1e-9))) {
    std::snprintf(text, sizeof text, "--graded-spacing %.3gmm (the horizons then follow the cells)",
                  std::max(size, p.spacing / 64) * 1e3);
    remedies.push_back(text);
  }
  remedies.push_back("a --spacing of about " + mm_text(size));
  return remedies;
}

std::string small_free_cells_cause(const SmallFreeCells& s, const ParticleSet& p) {
  char text[256];
  std::snprintf(text, sizeof text,
                "%zu free cells of %s (median) keep the horizon %s, about %.0f bonds each where %.0f is usual",
                s.small, mm_text(s.median_small_size).c_str(), mm_text(s.target_size * p.horizon_nominal / p.spacing).c_str(),
                s.small_family, s.usual_family);
  return text;
}

std::string small_free_cells_warning(const std::string& file, const SmallFreeCells& s, const ParticleSet& p,
                                     const std::vector<NarrowVoid>& narrow, const ResourceEstimate& grid,
                                     std::vector<std::string> remedies) {
  std::vector<const NarrowVoid*> culprits;
  std::size_t holes = 0;
  for (const auto& v : narrow)
    if (v.width < p.spacing) culprits.push_back(&v), holes += v.name.rfind("hole_", 0) == 0;
  std::string who;
  bool one = true;
  if (culprits.empty()) {
    // An outline traced as many short lines is sampled at its lines' ends;
    // one spline through the same points is sampled at about dx.
    char where[256];
    std::snprintf(where, sizeof where,
                  "a feature of the boundary near (%.4g, %.4g) mm (a short curve or a narrow gap; an outline traced "
                  "as many short lines meshes at the usual size drawn as one Spline through the same points)",
                  s.smallest_at.x * 1e3, s.smallest_at.y * 1e3);
    who = where;
  } else {
    double narrowest = culprits.front()->width, widest = narrowest;
    for (const auto* v : culprits) narrowest = std::min(narrowest, v->width), widest = std::max(widest, v->width);
    char wide[64];
    if (widest > narrowest * 1.01)
      std::snprintf(wide, sizeof wide, "%.3g to %.3g mm wide", narrowest * 1e3, widest * 1e3);
    else
      std::snprintf(wide, sizeof wide, "%.3g mm wide", narrowest * 1e3);
    const std::string narrower = "narrower than the spacing " + mm_text(p.spacing);
    const char* kind = holes == culprits.size() ? "holes" : holes == 0 ? "notches" : "voids";
    one = culprits.size() == 1;
    if (one)
      who = culprits[0]->name + " (" + wide + ", " + narrower + ")";
    else if (culprits.size() == 2)
      who = culprits[0]->name + " and " + culprits[1]->name + " (" + wide + ", " + narrower + ")";
    else
      who = std::to_string(culprits.size()) + " " + kind + " " + narrower + " (" + culprits[0]->name + ", " +
            culprits[1]->name + ", ...; " + wide + ")";
    remedies.push_back(std::string(kind) + " wider than the spacing");
  }
  const double m = p.horizon_nominal / p.spacing;
  char text[2048];
  std::snprintf(text, sizeof text,
                "%s: %s %s %zu free cells of %s (median) around %s, below half the %s their horizon %s is meant "
                "for: about %.0f bonds per particle there where %.0f is usual (%.3g bonds for %zu particles: about %s "
                "of memory and a %s file); %s give the usual families",
                file.c_str(), who.c_str(), one ? "forces" : "force", s.small, mm_text(s.median_small_size).c_str(),
                one ? "it" : "them", mm_text(s.target_size).c_str(), mm_text(s.target_size * m).c_str(),
                s.small_family, s.usual_family, grid.bonds, p.size(), format_bytes(grid.memory_bytes).c_str(),
                format_bytes(grid.file_bytes).c_str(), alternatives(remedies).c_str());
  return text;
}

}  // namespace pd
