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
  for (const char* f : {"crack_tips.csv", "crack_speed.csv", "branches.csv", "pore_trapping.csv", "summary.json",
                        "damage_final.png", "strain_energy_final.png", "damage_t10us.png", "speed_vs_time.png",
                        "speed_vs_x.png"})
    CHECK(fs::is_regular_file(post + "/" + f));
  // No snapshots in this output: the note says so, and no energy map at 10 us.
  CHECK_FALSE(fs::exists(post + "/strain_energy_t10us.png"));
  CHECK(std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) { return n.find("no snapshots") != std::string::npos; }));

  {
    std::ifstream f(post + "/crack_speed.csv");
    std::string header;
    std::getline(f, header);
    CHECK(header.rfind("time_s,branch,speed_m_per_s,speed_over_rayleigh", 0) == 0);
  }

  // Damage map of a 20 x 10 mm plate: 1000 x 500 px plot + margins = 1200 x 600.
  const Picture damage = read_png(post + "/damage_final.png");
  CHECK(damage.width == 1200);
  CHECK(damage.height == 600);
  // Intact particles are colormap(0), cracked ones colormap(1): the cracked
  // band is 3 x 130 particles of 2 x 2 px, partly under the tip path.
  CHECK(count(damage, colormap(0.0)) > 300000);
  CHECK(count(damage, colormap(1.0)) > 500);
  CHECK(count(damage, branch_color(0)) > 100);

  const Picture speed = read_png(post + "/speed_vs_time.png");
  CHECK(speed.width == 1000);
  CHECK(speed.height == 500);
  CHECK(count(speed, branch_color(0)) > 500);
}

TEST_CASE("snapshots give damage and strain-energy maps at the requested times", "[pictures]") {
  const auto dir = fresh_dir("snapshots");
  const Lattice lattice = make_lattice(20e-3, 10e-3, 0.1e-3);
  write_arrival_output(dir, lattice, crack_row, 30e-6);
  // Two snapshots at 5 and 20 us; the one at 20 us has damage 1 and energy
  // 7e5 J/m^3 everywhere, so a map asked for at 18 us (nearest: 20 us) is
  // all colormap(1).
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
  CHECK(r.notes.empty());
  const Picture damage = read_png(dir + "/post/damage_t18us.png");
  const Picture energy = read_png(dir + "/post/strain_energy_t18us.png");
  // Plot area 1000 x 500 px, less what the tip path and the frame cover.
  CHECK(count(damage, colormap(1.0)) > 480000);
  CHECK(count(energy, colormap(1.0)) > 480000);
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

TEST_CASE("legends list every branch, in a grid that grows by rows", "[pictures]") {
  // 20 x 10 mm plate (1200 x 600 px with a one-row legend) and 20 one-point
  // tip paths: "b0" ... "b19" need two rows beside a short title.
  const Lattice lattice = make_lattice(20e-3, 10e-3, 0.1e-3);
  ArrivalData data;
  data.x = lattice.x, data.y = lattice.y;
  data.cell_size.assign(lattice.x.size(), 0.1e-3);
  const std::vector<double> damage(lattice.x.size(), 0.0);
  const int n = 20;
  std::vector<TipPath> tips;
  std::vector<SpeedSample> samples;
  for (int b = 0; b < n; ++b) {
    tips.push_back({b, {0.0}, {(1 + 0.9 * b) * 1e-3}, {5e-3}});
    for (int k = 0; k < 2; ++k) samples.push_back({k * 1e-6, b, 1e-3, 300.0 + 10 * b, false});
  }
  MapStyle style;
  style.title = "t";
  const Canvas map = draw_particle_map(data, damage, style, tips, 1.0, {});
  CHECK(map.width() == 1200);
  CHECK(map.height() == 600 + 18);  // one more legend row in the top margin
  const Canvas speed = draw_speed_plot(samples, 938.0, SpeedAxis::time, {}, {}, "t");
  CHECK(speed.height() == 500);
  // Each legend swatch has a 10 x 10 px inside: the legend area holds 100 px
  // of a colour for each branch that has it (colours cycle every 8).
  auto swatch_pixels = [](const Canvas& c, int y0, int y1, Color col) {
    int found = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < c.width(); ++x) found += c.pixel(x, y) == col;
    return found;
  };
  for (int b = 0; b < 8; ++b) {
    if (branch_color(b) == white) continue;  // the legend's ground
    const int uses = (n - b + 7) / 8;        // branches b, b + 8, b + 16 below n
    CHECK(swatch_pixels(map, 0, 40 + 18, branch_color(b)) == 100 * uses);
    CHECK(swatch_pixels(speed, 40, 40 + 8 + 2 * 18, branch_color(b)) >= 100 * uses);
  }
}
