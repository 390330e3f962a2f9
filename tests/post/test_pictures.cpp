// The post directory: tables, summary and pictures of the documented size
// with content (damage colours, tip paths).
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "canvas.hpp"
#include "mesh_pictures.hpp"
#include "plots.hpp"
#include "post_pipeline.hpp"
#include "results_format.hpp"
#include "synthetic_output.hpp"
#include "vtk_output.hpp"

using namespace pd::post;
using namespace pd::post::test;
namespace fs = std::filesystem;

namespace {
struct Picture {
  int width = 0, height = 0;
  std::vector<Color> pixels;
};

Picture read_png(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  Picture p;
  p.width = dims[0], p.height = dims[1];
  const int comps = image->GetNumberOfScalarComponents();
  const auto* data = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (int k = 0; k < p.width * p.height; ++k)
    p.pixels.push_back({data[k * comps], data[k * comps + 1], data[k * comps + 2]});
  return p;
}

int count(const Picture& p, Color c) {
  int n = 0;
  for (auto q : p.pixels) n += q == c;
  return n;
}

double crack_row(double x, double y) {
  if (std::abs(y - 5.05e-3) > 0.101e-3 || x > 15e-3) return -1;
  return x <= 2e-3 ? 0.0 : (x - 2e-3) / 600.0;
}
}  // namespace

TEST_CASE("the post directory holds the tables, the summary and the pictures", "[pictures]") {
  const auto dir = fresh_dir("pictures");
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), crack_row, 30e-6, {0.2, 0.35});
  PostOptions o;
  o.outdir = dir;
  o.map_times = {10e-6};
  const PostResult r = run_post(o);

  const std::string post = dir + "/post";
  CHECK(r.main_picture == post + "/damage_final.png");
  CHECK(r.speed_table == post + "/crack_speed.csv");
  for (const char* f : {"crack_tips.csv", "crack_speed.csv", "branches.csv", "pore_trapping.csv",
                        "branching_events.csv", "summary.json", "damage_final.png", "strain_energy_final.png",
                        "damage_t10us.png", "speed_vs_time.png", "speed_vs_x.png"})
    CHECK(fs::is_regular_file(post + "/" + f));
  // No snapshots in this output: the note says so, and no energy map at 10 us.
  CHECK_FALSE(fs::exists(post + "/strain_energy_t10us.png"));
  CHECK_FALSE(fs::exists(post + "/cell_size_final.png"));  // one cell size: nothing to show
  CHECK(std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) { return n.find("no snapshots") != std::string::npos; }));

  {
    std::ifstream f(post + "/crack_speed.csv");
    std::string header;
    std::getline(f, header);
    CHECK(header.rfind("time_s,branch,speed_m_per_s,speed_over_rayleigh", 0) == 0);
  }

  // Damage map of a 20 x 10 mm plate, laid out as documented: 1000 x 500 px
  // plot, 80 + 120 px beside it; above it the legend band from 36 px (one
  // row of 18 px), 8 + 24 px for the colour bar's label; 60 px below.
  const Picture damage = read_png(post + "/damage_final.png");
  CHECK(damage.width == 1200);
  CHECK(damage.height == 36 + 18 + 8 + 24 + 500 + 60);
  // Intact particles are colormap(0), cracked ones colormap(1): the cracked
  // band is 3 x 130 particles of 2 x 2 px, partly under the tip path.
  CHECK(count(damage, colormap(0.0)) > 300000);
  CHECK(count(damage, colormap(1.0)) > 500);
  CHECK(count(damage, branch_color(0)) > 100);

  // Speed plot: 1000 px wide, legend row from 36 px, 12 px, 400 px plot, 60 px.
  const Picture speed = read_png(post + "/speed_vs_time.png");
  CHECK(speed.width == 1000);
  CHECK(speed.height == 36 + 18 + 12 + 400 + 60);
  CHECK(count(speed, branch_color(0)) > 500);
}

TEST_CASE("snapshot maps are named by the snapshot time they show", "[pictures]") {
  const auto dir = fresh_dir("snapshots");
  const Lattice lattice = make_lattice(20e-3, 10e-3, 0.1e-3);
  write_arrival_output(dir, lattice, crack_row, 30e-6);
  // Two snapshots at 5 and 20 us; the one at 20 us has damage 1 and energy
  // 7e5 J/m^3 everywhere, so a map asked for at 18 us shows the snapshot at
  // 20 us (all colormap(1)) and is named for 20 us.
  const std::size_t n = lattice.x.size();
  fs::create_directories(dir + "/snapshots");
  std::vector<std::pair<double, std::string>> entries;
  for (double t : {5e-6, 20e-6}) {
    const double level = t > 10e-6 ? 1.0 : 0.0;
    const std::string name = "snapshots/s" + std::to_string(static_cast<int>(t * 1e6)) + ".vtp";
    // Damage and strain energy in Float32, as pd-solve writes its snapshots.
    std::vector<pd::PointArray> arrays = {{pd::results::displacement, 3, std::vector<double>(3 * n, 0.0)},
                                          {pd::results::velocity, 3, std::vector<double>(3 * n, 0.0)},
                                          {pd::results::damage, 1},
                                          {pd::results::strain_energy_density, 1}};
    arrays[2].float_values.assign(n, static_cast<float>(level));
    arrays[3].float_values.assign(n, 7e5f);
    pd::write_vtp(dir + "/" + name, lattice.x, lattice.y, arrays,
                  {{pd::results::field_time, {t}}, {pd::results::field_step, {t / test_time_step}}});
    entries.emplace_back(t, name);
  }
  pd::write_pvd(dir + "/snapshots.pvd", entries);
  PostOptions o;
  o.outdir = dir;
  o.map_times = {18e-6};
  const PostResult r = run_post(o);
  CHECK_FALSE(fs::exists(dir + "/post/damage_t18us.png"));
  CHECK_FALSE(fs::exists(dir + "/post/strain_energy_t18us.png"));
  REQUIRE(r.maps.size() == 1);
  CHECK(r.maps[0].requested == 18e-6);
  CHECK(r.maps[0].used == 20e-6);
  // The note says which snapshot stands in for the time asked for.
  REQUIRE(r.notes.size() == 1);
  CHECK(r.notes[0].find("nearest snapshot, at 20 us") != std::string::npos);
  const Picture damage = read_png(dir + "/post/damage_t20us.png");
  const Picture energy = read_png(dir + "/post/strain_energy_t20us.png");
  // Plot area 1000 x 500 px, less what the tip path and the frame cover.
  CHECK(count(damage, colormap(1.0)) > 480000);
  CHECK(count(energy, colormap(1.0)) > 480000);
  // Every file pd-post wrote has one of its names (results::is_post_output),
  // which a later pd-solve run into this folder removes as earlier results.
  for (const auto& entry : fs::directory_iterator(dir + "/post")) {
    INFO(entry.path());
    CHECK(pd::results::is_post_output(entry.path().filename().string()));
  }
}

// A refined run's snapshots hold the particle set of their time, which is
// not the final one (docs/formats.md): drawn with their own particles and
// cell sizes. Reference: the plot area (1000 x 500 px) filled by the coarse
// set of the snapshot, damage 1 on its left half only (x < 10 mm).
TEST_CASE("a refined run's snapshot is drawn with its own particles", "[pictures]") {
  const auto dir = fresh_dir("refined_snapshot");
  const Lattice coarse = make_lattice(20e-3, 10e-3, 0.1e-3);
  const Lattice final_set = split_right_of(coarse, 10e-3);
  write_arrival_output(dir, final_set, crack_row, 30e-6);
  const std::size_t n = coarse.x.size();
  REQUIRE(final_set.x.size() != n);
  std::vector<float> damage(n);
  for (std::size_t i = 0; i < n; ++i) damage[i] = coarse.x[i] < 10e-3 ? 1.0f : 0.0f;
  const auto write_snapshot = [&](bool with_cell_size) {
    fs::create_directories(dir + "/snapshots");
    std::vector<pd::PointArray> arrays = {{pd::results::displacement, 3, std::vector<double>(3 * n, 0.0)},
                                          {pd::results::damage, 1}};
    arrays[1].float_values = damage;
    if (with_cell_size) arrays.push_back({pd::results::cell_size, 1, std::vector<double>(n, 0.1e-3)});
    pd::write_vtp(dir + "/snapshots/step_00000100.vtp", coarse.x, coarse.y, arrays,
                  {{pd::results::field_time, {5e-6}}, {pd::results::field_step, {100}}});
    pd::write_pvd(dir + "/snapshots.pvd", {{5e-6, "snapshots/step_00000100.vtp"}});
  };
  write_snapshot(true);
  PostOptions o;
  o.outdir = dir;
  o.map_times = {5e-6};
  run_post(o);
  const Picture map = read_png(dir + "/post/damage_t5us.png");
  const int half = 1000 * 500 / 2;
  CHECK(count(map, colormap(1.0)) > 0.95 * half);  // the damaged left half (the bar's top adds a little)
  CHECK(count(map, colormap(1.0)) < 1.05 * half);
  CHECK(count(map, colormap(0.0)) > 0.9 * half);   // the intact right half, less the tip path
  // Without its cell sizes a snapshot of another set cannot be drawn: an error naming both counts.
  write_snapshot(false);
  CHECK_THROWS_WITH(run_post(o), Catch::Contains("step_00000100.vtp") &&
                                     Catch::Contains("has " + std::to_string(n) + " particles, the run's final state has " +
                                                     std::to_string(final_set.x.size())));
}

TEST_CASE("text and lines land where they are drawn", "[pictures]") {
  Canvas c(40, 20);
  c.text(1, 1, "1", black, 1);
  // Glyph '1' row 0 is "..#..": pixel (1 + 2, 1) is set, (1, 1) is not.
  CHECK(c.pixel(3, 1) == black);
  CHECK(c.pixel(1, 1) == white);
  c.line(0, 15, 39, 15, Color{255, 0, 0});
  for (int x = 0; x < 40; ++x) CHECK(c.pixel(x, 15) == Color{255, 0, 0});
  CHECK(Canvas::text_width("ab", 2) == 2 * 12 - 2);
}

// A line is clipped to the canvas before it is stepped along. Before 7
// December 2026 the clipped part was sampled afresh, and its pixels landed
// up to one away from those of the same line drawn whole on a larger canvas
// (13 of the 40 x 30 canvas's pixels differed for these six lines).
TEST_CASE("a line partly off the canvas sets the pixels the same line sets on a canvas that holds it whole",
          "[pictures]") {
  const Color red{255, 0, 0};
  struct Segment {
    double x0, y0, x1, y1;
    int thickness;
  };
  // Each starts on the small canvas or off its left and top, and ends off its
  // right or bottom, on the large one.
  const std::vector<Segment> segments{{5.3, 7.1, 250.7, 80.4, 1},  {2.2, 28.6, 180.9, 3.3, 1},
                                      {-60.4, 2.7, 133.1, 29.9, 1}, {17.8, -90.2, 31.4, 270.6, 2},
                                      {1.6, 12.2, 390.3, 41.7, 3},  {-13.9, -8.4, 95.2, 77.7, 1}};
  int differing = 0;
  for (const auto& l : segments) {
    Canvas small(40, 30), large(400, 300);
    small.line(l.x0, l.y0, l.x1, l.y1, red, l.thickness);
    large.line(l.x0, l.y0, l.x1, l.y1, red, l.thickness);
    int drawn = 0;
    for (int y = 0; y < small.height(); ++y)
      for (int x = 0; x < small.width(); ++x) {
        drawn += small.pixel(x, y) == red;
        differing += !(small.pixel(x, y) == large.pixel(x, y));
      }
    CHECK(drawn > 0);  // each crosses the small canvas
  }
  CHECK(differing == 0);
}

// A reaction column of load_steps.csv from 1.7e308 N to -1.7e308 N (finite,
// as a table may hold them): the axis spans more than the largest double.
// Before 7 December 2026 its span overflowed to infinity, every pixel was a
// NaN: no curve in the plot, the markers cast to int from NaN (pixels at
// the picture's top edge), and the tick labels were cut off.
TEST_CASE("a line plot of values near the largest double draws its curve inside the plot", "[pictures]") {
  const Series column{"top_reaction_x_N", branch_style(3), {0.1, 0.2}, {1.7e308, -1.7e308}};
  const std::string title = "reactions against load factor";
  const Canvas c = draw_line_plot({column}, "load factor", "reaction (N)", title);
  const PictureLayout l = layout_line_plot(title, {{column.label, column.style}});
  int inside = 0, above_legend = 0;
  for (int y = 0; y < c.height(); ++y)
    for (int x = 0; x < c.width(); ++x) {
      if (!(c.pixel(x, y) == column.style.color)) continue;
      inside += x > l.plot.x0 && x < l.plot.x1 && y > l.plot.y0 && y < l.plot.y1;
      above_legend += y < l.legend.y0;
    }
  CHECK(inside > 100);  // the line across the plot, 2 px thick
  CHECK(above_legend == 0);
}

namespace {
// A map of a plate w x h [m] with `branches` one-point tip paths spread over it.
Canvas map_with_branches(double w, double h, int branches, const std::string& title, PictureLayout& layout) {
  const double spacing = std::max(w, h) / 200;
  const Lattice lattice = make_lattice(w, h, spacing);
  ArrivalData data;
  data.x = lattice.x, data.y = lattice.y;
  data.cell_size.assign(lattice.x.size(), spacing);
  std::vector<TipPath> tips;
  std::vector<int> ids;
  for (int b = 0; b < branches; ++b) {
    tips.push_back({b, {0.0}, {(0.5 + b) / branches * w}, {0.5 * h}});
    ids.push_back(b);
  }
  MapStyle style;
  style.title = title;
  layout = layout_particle_map(w, h, title, branch_legend_entries(ids));
  return draw_particle_map(data, std::vector<double>(lattice.x.size(), 0.0), style, tips, 1.0, {});
}

bool is_branch_colour(Color c, int branches) {
  for (int b = 0; b < branches; ++b)
    if (c == branch_color(b)) return true;
  return false;
}
}  // namespace

TEST_CASE("legends stay outside the map and off the title for any plate shape", "[pictures]") {
  const std::string title = "damage at 123.4 us, tips at damage 0.35";
  for (const auto& [w, h] : std::vector<std::pair<double, double>>{
           {50e-3, 25e-3}, {100e-3, 10e-3}, {20e-3, 20e-3}, {10e-3, 40e-3}, {4e-3, 50e-3}})
    for (int branches : {1, 8, 23, 40}) {
      INFO("plate " << w * 1e3 << " x " << h * 1e3 << " mm, " << branches << " branches");
      PictureLayout l;
      const Canvas c = map_with_branches(w, h, branches, title, l);
      CHECK(c.width() == l.width);
      CHECK(c.height() == l.height);
      const Box whole{0, 0, c.width(), c.height()};
      for (const Box* b : {&l.title, &l.legend, &l.plot, &l.bar}) {
        CHECK(b->x0 >= whole.x0);
        CHECK(b->x1 <= whole.x1);
        CHECK(b->y1 <= whole.y1);
      }
      CHECK_FALSE(overlap(l.title, l.legend));
      CHECK_FALSE(overlap(l.legend, l.plot));
      CHECK_FALSE(overlap(l.legend, l.bar));
      CHECK_FALSE(overlap(l.title, l.bar));
      CHECK_FALSE(overlap(l.title, l.plot));
      // On the picture: outside the plot, branch colours are in the legend
      // only, and every branch is there.
      int stray = 0;
      std::vector<int> in_legend(branches, 0);
      for (int y = 0; y < c.height(); ++y)
        for (int x = 0; x < c.width(); ++x) {
          const Color col = c.pixel(x, y);
          if (!is_branch_colour(col, branches) || l.plot.contains(x, y)) continue;
          if (!l.legend.contains(x, y)) ++stray;
          for (int b = 0; b < branches; ++b) in_legend[b] += col == branch_color(b);
        }
      CHECK(stray == 0);
      for (int b = 0; b < std::min(branches, branch_colour_count); ++b) CHECK(in_legend[b] > 20);
      // The title's own text is not painted over: its box holds black and white only.
      int foreign = 0;
      for (int y = l.title.y0; y < l.title.y1; ++y)
        for (int x = l.title.x0; x < l.title.x1; ++x)
          foreign += !(c.pixel(x, y) == black || c.pixel(x, y) == white);
      CHECK(foreign == 0);
    }
}

TEST_CASE("a tip path's jump across a pore is not drawn through the pore", "[pictures]") {
  // A 50 mm x 25 mm plate with a pore of radius 3 mm at its centre and one
  // branch whose tip runs along y = 12.5 mm, reaches the pore at x = 22 mm
  // and re-initiates on the far side at x = 28 mm: no crack runs through the
  // pore's inside, so the path has a gap there; the path on either side is
  // drawn. Without the pore the same path crosses the centre (the check can fail).
  const double w = 50e-3, h = 25e-3, spacing = 0.25e-3;
  const Lattice lattice = make_lattice(w, h, spacing);
  ArrivalData data;
  data.x = lattice.x, data.y = lattice.y;
  data.cell_size.assign(lattice.x.size(), spacing);
  const Pore pore = circle_pore(25e-3, 12.5e-3, 3e-3);
  const std::vector<double> xs{5e-3, 12e-3, 18e-3, 22e-3, 28e-3, 32e-3, 38e-3, 45e-3};
  const TipPath tip{0, {0, 1e-6, 2e-6, 3e-6, 4e-6, 5e-6, 6e-6, 7e-6}, xs, std::vector<double>(xs.size(), pore.y)};
  MapStyle style;
  style.title = "damage";
  const PictureLayout l = layout_particle_map(w, h, style.title, branch_legend_entries({0}));
  const auto pixel_x = [&](double x) { return static_cast<int>(std::lround(l.plot.x0 + x / w * (l.plot.x1 - l.plot.x0))); };
  const int row = static_cast<int>(std::lround(l.plot.y1 - pore.y / h * (l.plot.y1 - l.plot.y0)));
  const double px_per_m = (l.plot.x1 - l.plot.x0) / w;
  // Branch-coloured pixels within 0.6 radii of the pore's centre, and on the
  // path's row between 13 and 17 mm (a drawn segment away from any marker).
  const auto count = [&](const Canvas& c, int& inside, int& outside) {
    inside = outside = 0;
    const int cx = pixel_x(pore.x), r = static_cast<int>(0.6 * pore.radius * px_per_m);
    for (int y = row - r; y <= row + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
        if ((x - cx) * (x - cx) + (y - row) * (y - row) <= r * r) inside += c.pixel(x, y) == branch_color(0);
    for (int x = pixel_x(13e-3); x <= pixel_x(17e-3); ++x)
      for (int y = row - 1; y <= row + 1; ++y) outside += c.pixel(x, y) == branch_color(0);
  };
  const std::vector<double> zero(lattice.x.size(), 0.0);
  int inside = 0, outside = 0;
  count(draw_particle_map(data, zero, style, {tip}, 1.0, {pore}), inside, outside);
  CHECK(inside == 0);
  CHECK(outside > 20);
  count(draw_particle_map(data, zero, style, {tip}, 1.0, {}), inside, outside);
  CHECK(inside > 20);
}

TEST_CASE("every branch below 50 has its own style, mirror branches differ in colour, none is white", "[pictures]") {
  for (int a = 0; a < 50; ++a) {
    const Color c = branch_color(a);
    // Not white nor near it: it shows on the legend's white ground.
    CHECK(std::min({c.r, c.g, c.b}) <= 190);
    // The two children of a branching event have consecutive numbers.
    CHECK_FALSE(branch_color(a) == branch_color(a + 1));
    for (int b = a + 1; b < 50; ++b) {
      INFO("branches " << a << " and " << b);
      CHECK_FALSE(branch_style(a) == branch_style(b));
    }
  }
}

TEST_CASE("speed plots list their branches in a band above the plot", "[pictures]") {
  std::vector<SpeedSample> samples;
  const int n = 20;
  for (int b = 0; b < n; ++b)
    for (int k = 0; k < 30; ++k) samples.push_back({k * 1e-7, b, 1e-3, 300.0 + 10 * b, false});
  const std::string title = "crack speed per branch";
  const Canvas speed = draw_speed_plot(samples, 938.0, SpeedAxis::time, {}, {}, title);
  std::vector<int> ids(n);
  for (int b = 0; b < n; ++b) ids[b] = b;
  const PictureLayout l = layout_line_plot(title, branch_legend_entries(ids));
  CHECK(l.legend_grid.rows == 2);  // 20 entries of 54 px in 984 px: 18 a row
  CHECK(speed.height() == 36 + 2 * 18 + 12 + 400 + 60);
  CHECK_FALSE(overlap(l.legend, l.plot));
  CHECK_FALSE(overlap(l.legend, l.title));
  for (int b = 0; b < branch_colour_count; ++b) {
    int found = 0;
    for (int y = l.legend.y0; y < l.legend.y1; ++y)
      for (int x = l.legend.x0; x < l.legend.x1; ++x) found += speed.pixel(x, y) == branch_color(b);
    CHECK(found > 20);
  }
}

TEST_CASE("a run whose cells differ in size gets a map of the cell sizes", "[pictures]") {
  // The 20 x 10 mm plate with its right half split into quarters, as a
  // refinement event splits squares: 0.05 mm cells right of x = 10 mm, 0.1 mm
  // left of it. The map's scale runs from the smallest cell (colormap(0)) to
  // the largest (colormap(1)); each half fills about half the plot of 1000 x 500 px.
  const auto dir = fresh_dir("cell_sizes");
  write_arrival_output(dir, split_right_of(make_lattice(20e-3, 10e-3, 0.1e-3), 10e-3), crack_row, 30e-6);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = run_post(o);
  const std::string map = dir + "/post/cell_size_final.png";
  REQUIRE(fs::is_regular_file(map));
  CHECK(std::find(r.pictures.begin(), r.pictures.end(), map) != r.pictures.end());
  const Picture cells = read_png(map);
  const int half = 1000 * 500 / 2;
  CHECK(count(cells, colormap(1.0)) > 0.9 * half);  // coarse left half (the bar's top adds a little)
  CHECK(count(cells, colormap(1.0)) < 1.1 * half);
  CHECK(count(cells, colormap(0.0)) > 0.9 * half);  // fine right half, less the tip path's pixels
  CHECK(count(cells, colormap(0.0)) < 1.1 * half);
  CHECK(count(cells, branch_color(0)) > 100);        // the tip path drawn over it
}

// Reference: pixel counts by construction. A 100 x 60 field of 10-pixel
// squares with a 2 x 2 gap, a 1 x 3 gap and a 4 x 4 gap between them (what
// free cells drawn as squares of their area leave), a 20 x 20 hole, and the
// field's edge: the gaps are filled with their neighbours' colour, the hole
// and the outside stay background.
TEST_CASE("pinholes between drawn cells are filled, holes and edges are not", "[pictures]") {
  Canvas c(140, 100);
  const Color cell{10, 200, 30};
  c.fill_rect(20, 20, 120, 80, cell);
  c.fill_rect(40, 30, 42, 32, white);  // 2 x 2
  c.fill_rect(60, 30, 61, 33, white);  // 1 x 3
  c.fill_rect(80, 30, 84, 34, white);  // 4 x 4: the largest patch filled
  c.fill_rect(70, 50, 90, 70, white);  // a hole of 400 pixels
  c.fill_pinholes(0, 0, 140, 100);
  for (const auto& [x, y] : {std::pair{40, 30}, {41, 31}, {60, 32}, {83, 33}, {81, 31}}) CHECK(c.pixel(x, y) == cell);
  for (const auto& [x, y] : {std::pair{70, 50}, {80, 60}, {89, 69}, {5, 5}, {19, 50}}) CHECK(c.pixel(x, y) == white);
  // A 5 x 5 patch is more than 16 pixels: kept, as a small hole would be.
  c.fill_rect(100, 30, 105, 35, white);
  c.fill_pinholes(0, 0, 140, 100);
  CHECK(c.pixel(102, 32) == white);
}

namespace {
// Two 1 mm square cells side by side, their particles at the centres.
pd::ParticleSet two_square_cells() {
  pd::ParticleSet p;
  p.spacing = 1e-3;
  p.xmin = 0, p.xmax = 2e-3, p.ymin = 0, p.ymax = 1e-3;
  p.cell_offsets = {0};
  for (const double x0 : {0.0, 1e-3}) {
    p.x.push_back(x0 + 0.5e-3), p.y.push_back(0.5e-3);
    for (const auto& [vx, vy] : {std::pair{x0, 0.0}, {x0 + 1e-3, 0.0}, {x0 + 1e-3, 1e-3}, {x0, 1e-3}})
      p.cell_vx.push_back(vx), p.cell_vy.push_back(vy);
    p.cell_offsets.push_back(p.cell_vx.size());
  }
  return p;
}
}  // namespace

// A window far taller than wide (pd-post --particles P --zoom with x0 and x1
// a few um apart, y over the plate): before 7 December 2026 its plot was
// lround(700 px x 0.4 um / 1 mm) = 0 px wide, no cell drawn (exit 0), and the
// title cut at the picture's edge, 280 px from the left.
TEST_CASE("a cell map of a narrow window keeps a plot 100 px wide and its whole title", "[pictures]") {
  const pd::ParticleSet p = two_square_cells();
  const Color cells{255, 160, 60};
  const std::string title = "nbnug grid, dx 1.000 mm, 2 particles: region";
  const Canvas map = draw_cell_map(p, {cells, cells}, {0.9998e-3, 1.0002e-3, 0.0, 1e-3}, title, nullptr, {});
  const auto count = [](const Canvas& c, Color colour, int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) n += c.pixel(x, y) == colour ? 1 : 0;
    return n;
  };
  // The plot: 100 x 700 px from (80, 40), filled by the two cells but for
  // the frame and the grey edge between them (the window is inside both).
  CHECK(count(map, cells, 0, 0, map.width(), map.height()) >= 0.9 * 100 * 700);
  CHECK(count(map, cells, 181, 0, map.width(), map.height()) == 0);
  // The title (from 12 px, above the frame at 40 px) as drawn alone.
  Canvas alone(Canvas::text_width(title) + 10, 20);
  alone.text(0, 0, title, black);
  const int title_pixels = count(alone, black, 0, 0, alone.width(), alone.height());
  REQUIRE(title_pixels > 100);
  CHECK(count(map, black, 80, 12, map.width(), 32) == title_pixels);
  // With a colour bar, whose label stands above it: clear of the title.
  MapStyle bar;
  bar.bar_label = "V / dx^2";
  bar.vmin = 0.25, bar.vmax = 2.0;
  const Canvas with_bar = draw_cell_map(p, {cells, cells}, {0.9998e-3, 1.0002e-3, 0.0, 1e-3}, title, &bar, {});
  CHECK(count(with_bar, black, 80, 12, with_bar.width(), 32) == title_pixels);
  CHECK(count(with_bar, cells, 0, 0, with_bar.width(), with_bar.height()) >= 0.9 * 100 * 700);
}

// The region picture of a particle file (pd-post --particles) names its
// cells in a legend beside the map. Its longest label, "near-boundary
// quads" (226 px from 42 px beside the plot), was cut after
// "near-boundary" by a margin of 200 px; every pixel of the label as
// drawn alone must now be on the picture, inside its right edge.
TEST_CASE("a cell map's legend shows its longest label whole", "[pictures]") {
  const pd::ParticleSet p = two_square_cells();
  const Color cells{255, 160, 60};
  const std::string label = "near-boundary quads";
  const Canvas map = draw_cell_map(p, {cells, cells}, {}, "cells", nullptr, {{cells, label}});
  Canvas alone(Canvas::text_width(label) + 10, 20);
  alone.text(0, 0, label, black);
  const auto black_pixels = [](const Canvas& c, int x0, int y0, int x1, int y1, int* rightmost) {
    int count = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        if (c.pixel(x, y) == black) ++count, *rightmost = std::max(*rightmost, x);
    return count;
  };
  int rightmost_alone = 0, rightmost = 0;
  const int label_pixels = black_pixels(alone, 0, 0, alone.width(), alone.height(), &rightmost_alone);
  REQUIRE(label_pixels > 100);
  // The plot spans 80 to 1080 px (2 x 1 mm at 1000 px wide), the label's
  // row 40 to 56 px from 1122 px; left of 1100 px lie the plot and its frame.
  CHECK(black_pixels(map, 1100, 40, map.width(), 58, &rightmost) == label_pixels);
  CHECK(rightmost == 1122 + rightmost_alone);
  CHECK(rightmost < map.width() - 8);
}

// A window a few 1e-19 m wide around a particle's centre: 1000 px times its
// aspect ratio (1e16) is more than a long holds, and before 7 December 2026
// lround's overflow made the plot 1000 x 100 px, flat instead of tall.
TEST_CASE("a cell map of a window far narrower than any cell is drawn tall, its aspect never cast", "[pictures]") {
  const pd::ParticleSet p = two_square_cells();
  const Color cells{255, 160, 60};
  const Canvas map = draw_cell_map(p, {cells, cells}, {0.5e-3, 0.5e-3 + 1e-19, 0.0, 1e-3}, "cells", nullptr, {});
  CHECK(map.height() == 40 + 700 + 60);
  int filled = 0;
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) filled += map.pixel(x, y) == cells ? 1 : 0;
  CHECK(filled >= 0.9 * 100 * 700);
}

namespace {
// A 50 x 25 mm plate from (0, 100) mm, taller in its coordinates than wide
// (a window's four lengths typed as --line's fall off it): the centres of
// its 1 mm cells.
pd::ParticleSet raised_plate() {
  pd::ParticleSet p;
  p.spacing = 1e-3;
  p.xmin = 0, p.xmax = 50e-3, p.ymin = 100e-3, p.ymax = 125e-3;
  for (int j = 0; j < 25; ++j)
    for (int i = 0; i < 50; ++i) p.x.push_back((i + 0.5) * 1e-3), p.y.push_back(100e-3 + (j + 0.5) * 1e-3);
  return p;
}
std::vector<double> mm(std::vector<double> values) {
  for (double& v : values) v *= 1e-3;
  return values;
}
}  // namespace

// --zoom takes x0,x1,y0,y1, --line x0,y0,x1,y1. Before 7 December 2026 a
// window typed in the order of --line that stayed ordered was drawn without
// a word (here x 10 to 105 mm, y 40 to 120 mm, 11 % of it on the plate),
// and a window in m for mm drew the plate as a dot.
TEST_CASE("a zoom window mostly off the plate that the other order puts on it is warned about, and a far larger one "
          "is clipped", "[pictures][bad-input]") {
  const pd::ParticleSet p = raised_plate();
  const std::string plate = "the plate (x in [0, 50] mm, y in [100, 125] mm)";
  ZoomWindow z = checked_zoom_window(p, "plate.pdp", mm({10, 105, 40, 120}));
  REQUIRE(z.warnings.size() == 1);
  CHECK(z.warnings[0] == "--zoom 10, 105, 40, 120 mm is read as x0,x1,y0,y1: x in [10, 105] mm, y in [40, 120] mm, "
                         "mostly off the plate (x in [0, 50] mm, y in [100, 125] mm); read as x0,y0,x1,y1, the order "
                         "of --line, it would lie on the plate (x in [10, 40] mm, y in [105, 120] mm): for that "
                         "window give --zoom 10mm,40mm,105mm,120mm");
  CHECK(z.window == mm({10, 105, 40, 120}));  // drawn as given: its meaning stays
  // The window meant, and one partly off the plate, drawn without a word.
  for (const auto& window : {mm({10, 40, 105, 120}), mm({40, 60, 110, 120}), mm({-5, 55, 95, 130})}) {
    z = checked_zoom_window(p, "plate.pdp", window);
    CHECK(z.warnings.empty());
    CHECK(z.window == window);
  }
  // Metres for millimetres: clipped to the plate's bounding box.
  z = checked_zoom_window(p, "plate.pdp", {-1, 1, -1, 1});
  CHECK(z.window == mm({0, 50, 100, 125}));
  REQUIRE(z.warnings.size() == 1);
  CHECK(z.warnings[0] == "--zoom: the window x in [-1000, 1000] mm, y in [-1000, 1000] mm is more than 10 times as "
                         "wide and as tall as the part of the plate it holds (the plate spans x in [0, 50] mm, y in "
                         "[100, 125] mm): drawn clipped to the plate, x in [0, 50] mm, y in [100, 125] mm (are its "
                         "lengths in the unit meant?)");
  // One way only: the other side as given.
  z = checked_zoom_window(p, "plate.pdp", mm({10, 40, -500, 500}));
  CHECK(z.window == mm({10, 40, 100, 125}));
  REQUIRE(z.warnings.size() == 1);
  CHECK_THAT(z.warnings[0], Catch::Contains("is more than 10 times as tall as the part of the plate it holds"));
  // A window without a particle centre stays refused.
  CHECK_THROWS_WITH(checked_zoom_window(p, "plate.pdp", mm({60, 70, 100, 125})),
                    Catch::Contains("holds no particle centre of plate.pdp"));
}
