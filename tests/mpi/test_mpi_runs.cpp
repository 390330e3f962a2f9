// pd-solve on several MPI processes (docs/solver.md, "Running on several
// processes (MPI)"), on a cracking plate: case C3-A (geometries/c3a_pores.geo,
// the perforated PMMA plate with the long pre-crack of geometries/c3a_long.toml)
// at dx = 0.3125 mm, delta = 1.25 mm (m = 4, about 12,800 particles), loaded
// faster than the paper's case (1.5 m/s ramped over 20 us instead of 0.3 m/s
// over 200 us) so that the crack grows from the pre-crack tip within 45 us.
//
// Reference: the same scene on one process, with the kernels a one-process
// run uses (the float lattice sweep for the squares, the neighbour lists for
// the other particles); it runs in this test's process. A distributed run
// sweeps each slab's lattice squares and their ghosts and evaluates every
// bond of an owned particle with the same operations in the same order on
// the same numbers (ghost displacements arrive bit for bit, and the sweep
// adds each cell's float sums in the one-process order: lattice_kernel.hpp),
// so broken bonds, damage and displacements agree to round-off (1e-12: far
// below the float sweep's own round-off of about 1e-7, so a pair evaluated
// differently would show); only the sums over particles (energies,
// reactions, external work) add their per-process parts in another order,
// so energy rows agree to 1e-9 of the total energy (the rows are printed
// with 9 digits: a 1e-8 tolerance).
//
// The same plate with ordinary state-based PD (OSB, theory.md Sec. 5) checks
// the second exchange of a step: each process computes the dilatations of
// its owned particles from their whole families, and the ghosts' theta / m
// arrive from their owners before the forces read them at both ends of a
// bond; with them, every owned particle's force is again the one-process
// force bit for bit, so the same tolerances hold.
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

// (the event listener below removes the folders of passed cases)
#define CATCH_CONFIG_EXTERNAL_INTERFACES
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../test_commands.hpp"
#include "../test_folder.hpp"
#include "compact_families.hpp"
#include "results_format.hpp"
#include "scene.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;
using namespace pd::solver;
using pd::test_support::file_text;
using pd::test_support::run_shell;

namespace {

// The folders this process made for the running test case: removed when it
// passes (CTest runs each case in its own process, under tmp/<pid>), kept
// for a look when it fails.
std::vector<fs::path>& folders_of_running_case() {
  static std::vector<fs::path> folders;
  return folders;
}
std::string case_folder(const std::string& name) {
  const std::string folder = pd::test_support::fresh_folder_under(PD_MPI_TEST_TMPDIR, name);
  folders_of_running_case().push_back(folder);
  return folder;
}
struct RemoveFoldersOfPassedCase : Catch::TestEventListenerBase {
  using TestEventListenerBase::TestEventListenerBase;
  void testCaseEnded(const Catch::TestCaseStats& stats) override {
    auto& folders = folders_of_running_case();
    if (stats.totals.assertions.failed == 0) {
      std::error_code ignored;
      for (const fs::path& folder : folders) {
        fs::remove_all(folder, ignored);
        fs::remove(folder.parent_path(), ignored);  // tmp/<pid>, once empty
      }
    }
    folders.clear();
  }
};

const long energy_interval = 25;

// The folder of one test case with the C3-A particle file and the scene.
struct Case {
  std::string folder, particles, scene;
  double end_time = 0;  // s
  bool surface_correction = true;  // the scene's effects.surface_correction
};

// The load: the speed of both edges [m/s], reached over the ramp [s], and the end of the run [s].
struct Loading {
  double speed = 1.5, ramp = 2e-5, end = 45e-6;
};

// `model`: the scene's model.type ("pmb" or "osb"); `grid`: pd-mesh's
// options of spacing, horizon and grid; `dual_horizon`: empty for a particle
// file with one horizon (surface correction on), else the value of
// model.dual_horizon ("true" or "false") for one with variable horizons
// (surface correction off: not available with them).
const std::string lattice_grid = "--spacing 0.3125mm --horizon 1.25mm";
Case make_case(const std::string& name, const std::string& model = "pmb", const std::string& grid = lattice_grid,
               const std::string& dual_horizon = "", const Loading& loading = {}) {
  Case c;
  c.end_time = loading.end;
  c.surface_correction = dual_horizon.empty();
  c.folder = case_folder(name);
  c.particles = c.folder + "/c3a.pdp";
  REQUIRE(run_shell(std::string("\"") + PD_MESH_EXECUTABLE + "\" \"" + PD_GEOMETRY_DIR +
                    "/c3a_pores.geo\" " + grid + " -o \"" + c.particles + "\" > \"" +
                    c.folder + "/mesh.log\" 2>&1") == 0);
  // geometries/c3a_long.toml with a faster load and a shorter run.
  c.scene = c.folder + "/c3a_fast.toml";
  std::ofstream(c.scene) << "particles = \"c3a.pdp\"\n"
                         << "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
                            "thickness = 1.0\nplane = \"stress\"\npoisson_ratio = 0.35\n"
                         << "[model]\ntype = \"" << model << "\"\n"
                         << (dual_horizon.empty() ? "" : "dual_horizon = " + dual_horizon + "\n")
                         << "[effects]\ndamage = true\nsurface_correction = " << (dual_horizon.empty() ? "true" : "false")
                         << "\n"
                         << "[time]\nstep = \"auto\"\nend = " << loading.end << "\n"
                         << "[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = " << loading.speed
                         << "\nramp_time = " << loading.ramp << "\n"
                         << "[[loads]]\nset = \"bottom\"\ntype = \"velocity\"\ny = " << -loading.speed
                         << "\nramp_time = " << loading.ramp << "\n"
                         << "[[precracks]]\nfrom = [0.0, 0.0125]\nto = [0.002, 0.0125]\n"
                         << "[output]\nsnapshot_interval = 0\nenergy_interval = " << energy_interval
                         << "\ncheckpoint_interval = 0\n";
  return c;
}

// The case's scene with effects.surface_correction = `on`.
void set_surface_correction(Case& c, bool on) {
  std::string scene = file_text(c.scene);
  const std::string key = "surface_correction = ";
  const auto at = scene.find(key);
  REQUIRE(at != std::string::npos);
  scene.replace(at + key.size(), scene.find('\n', at) - at - key.size(), on ? "true" : "false");
  std::ofstream(c.scene) << scene;
  c.surface_correction = on;
}

// pd-solve on `processes` MPI processes, one thread each; its exit status.
int run_on_processes(const Case& c, int processes, const std::string& out, const std::string& extra = "") {
  std::ostringstream command;
  command << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " " << processes << " " << PD_MPIEXEC_PREFLAGS << " \""
          << PD_SOLVE_EXECUTABLE << "\" \"" << c.scene << "\" --threads 1 -q -o \"" << out << "\" " << extra << " > \""
          << out << ".log\" 2>&1";
  return run_shell(command.str());
}

// A point array of a .vtp file, all components.
std::vector<double> vtp_array(const std::string& file, const std::string& name) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkDataArray* a = reader->GetOutput()->GetPointData()->GetArray(name.c_str());
  REQUIRE(a != nullptr);
  std::vector<double> values(static_cast<std::size_t>(a->GetNumberOfTuples() * a->GetNumberOfComponents()));
  for (vtkIdType t = 0; t < a->GetNumberOfTuples(); ++t)
    for (int k = 0; k < a->GetNumberOfComponents(); ++k)
      values[static_cast<std::size_t>(t * a->GetNumberOfComponents() + k)] = a->GetComponent(t, k);
  return values;
}

// The rows of energy.csv as numbers.
std::vector<std::vector<double>> energy_rows(const std::string& out) {
  std::istringstream in(file_text(out + "/energy.csv"));
  std::string header, line;
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) rows.push_back(pd::test_support::csv_numbers(header, line));
  return rows;
}

// The one-process reference, stepped as pd-solve steps (energy rows every
// energy_interval steps, whose steps sum the strain energy in the sweep):
// its energy rows (time, step, kinetic, strain, external work, total - work,
// broken bonds), the end state and how many particles the sweep computes.
struct Reference {
  std::vector<std::vector<double>> rows;
  std::vector<double> damage, displacement;  // displacement: x, y, 0 per particle
  std::size_t particles = 0, lattice_particles = 0;
  std::uint64_t directed_bonds = 0;
  std::size_t precrack_bonds_cut = 0;
  double stable_time_step = 0;  // [s]
};

// `lattice_kernel` off: every bond on the neighbour lists (the rows of a
// variable-horizon run, as several processes run it).
Reference one_process_reference(const Case& c, bool lattice_kernel = true) {
  const Scene scene = read_scene(c.scene);
  auto read = pd::read_compact_particle_file(scene.particle_file);
  SetupOptions options;
  options.lattice_kernel = lattice_kernel;
  Simulation sim(scene, std::move(read.particles), std::move(read.families), options);
  Reference r;
  r.particles = sim.particle_count();
  r.lattice_particles = sim.lattice_particle_count();
  r.directed_bonds = sim.bond_count();
  r.precrack_bonds_cut = sim.precrack_bonds_cut();
  r.stable_time_step = sim.stable_time_step();
  const auto row = [&] {
    const EnergyTotals e = sim.energies();
    r.rows.push_back({sim.time(), static_cast<double>(sim.step_index()), e.kinetic, e.strain, e.external_work,
                      e.kinetic + e.strain - e.external_work, static_cast<double>(sim.broken_bond_count())});
  };
  row();
  const long steps = static_cast<long>(std::ceil(c.end_time / sim.time_step() - 1e-9));
  while (sim.step_index() < steps) {
    sim.step((sim.step_index() + 1) % energy_interval == 0);
    if (sim.step_index() % energy_interval == 0) row();
  }
  if (sim.step_index() % energy_interval != 0) row();
  r.damage = sim.damage();
  r.displacement = sim.displacement_xyz();
  return r;
}

// The distributed run's output against the reference; the crack must have
// grown through at least `damaged_at_least` particles (damage >= 0.35).
void check_against_reference(const std::string& out, const Reference& reference, long damaged_at_least = 50) {
  const auto damage = vtp_array(out + "/arrival.vtp", "damage");
  const auto displacement = vtp_array(out + "/arrival.vtp", "displacement");
  REQUIRE(damage.size() == reference.damage.size());
  REQUIRE(displacement.size() == reference.displacement.size());
  // The crack grew: a test on an uncracked plate would not see the bonds break.
  const auto damaged = std::count_if(damage.begin(), damage.end(), [](double d) { return d >= 0.35; });
  CHECK(damaged > damaged_at_least);
  double largest_u = 0, damage_difference = 0, displacement_difference = 0;
  for (std::size_t i = 0; i < damage.size(); ++i) damage_difference = std::max(damage_difference, std::fabs(damage[i] - reference.damage[i]));
  // arrival.vtp holds the displacement in Float32 (docs/formats.md): the
  // reference rounded so, the two agree to a Float32 step at most (values a
  // hair apart may round to neighbouring floats); the energy rows below
  // compare the runs in double.
  for (std::size_t k = 0; k < displacement.size(); ++k) {
    largest_u = std::max(largest_u, std::fabs(reference.displacement[k]));
    const double rounded = static_cast<float>(reference.displacement[k]);
    displacement_difference = std::max(displacement_difference, std::fabs(displacement[k] - rounded));
  }
  CHECK(damage_difference <= 1e-12);
  CHECK(displacement_difference <= 1.2e-7 * largest_u);

  const auto rows = energy_rows(out);
  REQUIRE(rows.size() == reference.rows.size());
  double scale = 0;  // the largest energy of the run [J]
  for (const auto& r : reference.rows) scale = std::max({scale, std::fabs(r[2]), std::fabs(r[3]), std::fabs(r[4])});
  for (std::size_t m = 0; m < rows.size(); ++m) {
    INFO("energy row " << m);
    CHECK(rows[m][1] == reference.rows[m][1]);  // step
    for (int column : {2, 3, 4, 5}) CHECK(std::fabs(rows[m][column] - reference.rows[m][column]) <= 1e-8 * scale);
    CHECK(rows[m][6] == reference.rows[m][6]);  // broken bonds, exactly
  }
}

// How often `what` occurs in `text`.
std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++count;
  return count;
}

// A refusal said once, by the root alone, as on one process: one error line,
// no process's rank before it and no MPI_Abort banner after it.
void check_said_once_by_the_root(const std::string& log) {
  CHECK(occurrences(log, "pd-solve: error:") == 1);
  CHECK(occurrences(log, "process 0 of 2") + occurrences(log, "process 1 of 2") == 0);
  CHECK(occurrences(log, "MPI_ABORT") == 0);
}

// The number after "key": in a summary.json text (NaN if the key is absent).
double summary_number(const std::string& summary, const std::string& key) {
  const auto at = summary.find("\"" + key + "\": ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(summary.substr(at + key.size() + 4));
}

// The time of the exchanges' finishing halves (waiting, unpacking) is a
// part of their whole time, reported separately.
void check_exchange_times(const std::string& out) {
  const std::string summary = file_text(out + "/summary.json");
  const double whole = summary_number(summary, "ghost_update_seconds_max");
  const double waiting = summary_number(summary, "ghost_wait_seconds_max");
  CHECK(whole > 0);
  CHECK(waiting >= 0);
  CHECK(waiting <= whole);
}

// A run on `from` processes stopped at `stop_fraction` of its end time and
// restarted on `to` processes from its last checkpoint (every
// `checkpoint_interval` steps) against the uninterrupted run on `from`
// processes (folders whole_FROM and parts_FROM_TO of the case). One process
// and several make the same damage, displacements and arrival times bit for
// bit, so a restart across them must too (docs/solver.md, "Safety").
void check_restart_on_other_process_count(const Case& c, long checkpoint_interval = 100, double stop_fraction = 0.5,
                                          int from = 2, int to = 3) {
  const std::string whole = c.folder + "/whole_" + std::to_string(from),
                    parts = c.folder + "/parts_" + std::to_string(from) + "_" + std::to_string(to);
  const std::string checkpoints = "--set output.checkpoint_interval=" + std::to_string(checkpoint_interval);
  if (!fs::exists(whole + "/summary.json")) REQUIRE(run_on_processes(c, from, whole, checkpoints) == 0);
  // Stop early (after the first checkpoint), then continue to the end.
  REQUIRE(run_on_processes(c, from, parts,
                           checkpoints + " --set time.end=" + std::to_string(c.end_time * stop_fraction)) == 0);
  REQUIRE(run_on_processes(c, to, parts, checkpoints + " --restart") == 0);
  // Damage, displacements and arrival times bit for bit (the same operations
  // on the same numbers); energy rows to the round-off of the sums' order.
  for (const std::string array : {"damage", "displacement", "arrival_time_0.35"})
    CHECK(vtp_array(whole + "/arrival.vtp", array) == vtp_array(parts + "/arrival.vtp", array));
  const auto a = energy_rows(whole), b = energy_rows(parts);
  REQUIRE(a.size() == b.size());
  double scale = 0;
  for (const auto& r : a) scale = std::max({scale, std::fabs(r[2]), std::fabs(r[3]), std::fabs(r[4])});
  for (std::size_t m = 0; m < a.size(); ++m)
    for (std::size_t column = 0; column < a[m].size(); ++column)
      CHECK(std::fabs(a[m][column] - b[m][column]) <= 1e-8 * scale + 1e-8 * std::fabs(a[m][column]));
}

}  // namespace

CATCH_REGISTER_LISTENER(RemoveFoldersOfPassedCase)

TEST_CASE("C3-A on 2 processes: the damage and displacements of one process, energies to round-off", "[mpi]") {
  const Case c = make_case("two");
  const std::string out = c.folder + "/run2";
  REQUIRE(run_on_processes(c, 2, out) == 0);
  const Reference reference = one_process_reference(c);
  check_against_reference(out, reference);
  // The plan names the decomposition, and the processes sweep the lattice
  // squares of one process, all of them (their owned ones summed): most of
  // the plate (60 % at this coarse spacing, 96 % at the paper's), the rest
  // (near the holes, edges and pre-crack) on the lists.
  const std::string log = file_text(out + ".log");
  CHECK(log.find("2 processes") != std::string::npos);
  CHECK(reference.lattice_particles > reference.particles / 2);
  CHECK(log.find("lattice sweep for " + std::to_string(reference.lattice_particles) + " particles, neighbour lists for " +
                 std::to_string(reference.particles - reference.lattice_particles)) != std::string::npos);
  check_exchange_times(out);
}

TEST_CASE("C3-A on 3 processes (oversubscribed): the same as one process", "[mpi]") {
  const Case c = make_case("three");
  const std::string out = c.folder + "/run3";
  REQUIRE(run_on_processes(c, 3, out) == 0);
  check_against_reference(out, one_process_reference(c));
}


TEST_CASE("a 2-process run restarted on 3 processes ends as the uninterrupted 2-process run", "[mpi][restart]") {
  check_restart_on_other_process_count(make_case("restart"));
}

// Between one process and several (since 8 December 2026; before, refused
// by the checkpoint's key: 'checkpoint was written by a run on one process,
// and this run is on several: restart it on one process (without mpirun)',
// and the other way round). One process saves its bond states in its
// kernels' layout, which the root turns family by family at the restart on
// several; one process places a checkpoint of several family by family.
// Stopped at 22.5 us, restarted from step 100, after the crack has started.
TEST_CASE("a one-process run restarted on 2 processes ends as the uninterrupted one-process run",
          "[mpi][restart]") {
  const Case c = make_case("restart_1_2");
  check_restart_on_other_process_count(c, 100, 0.5, 1, 2);
  // One process and two: the same arrays bit for bit, so the restart's
  // equality above is the uninterrupted run's on either count.
  REQUIRE(run_on_processes(c, 2, c.folder + "/whole_2") == 0);
  for (const std::string array : {"damage", "displacement", "arrival_time_0.35"})
    CHECK(vtp_array(c.folder + "/whole_1/arrival.vtp", array) == vtp_array(c.folder + "/whole_2/arrival.vtp", array));
}

TEST_CASE("a 2-process run restarted on one process ends as the uninterrupted 2-process run", "[mpi][restart]") {
  check_restart_on_other_process_count(make_case("restart_2_1"), 100, 0.5, 2, 1);
}

// OSB: the sweep's pair bits and the dilatation pass restored either way.
TEST_CASE("an OSB run restarted from one process on 2, and from 2 on one, ends as the uninterrupted run",
          "[mpi][osb][restart]") {
  const Case c = make_case("osb_restart_1_2", "osb");
  check_restart_on_other_process_count(c, 100, 0.5, 1, 2);
  check_restart_on_other_process_count(c, 100, 0.5, 2, 1);
}

TEST_CASE("C3-A with OSB on 2 and 3 processes: the damage and displacements of one process", "[mpi][osb]") {
  const Case c = make_case("osb", "osb");
  const std::string out2 = c.folder + "/run2", out3 = c.folder + "/run3";
  REQUIRE(run_on_processes(c, 2, out2) == 0);
  REQUIRE(run_on_processes(c, 3, out3) == 0);
  const Reference reference = one_process_reference(c);
  check_against_reference(out2, reference);
  check_against_reference(out3, reference);
  // The summary counts both exchanges of a step (displacements, theta / m).
  const std::string summary = file_text(out2 + "/summary.json");
  CHECK(summary.find("\"ghost_exchanges_per_step\": 2") != std::string::npos);
  check_exchange_times(out2);
}

TEST_CASE("OSB on the neighbour lists alone (a free grid) on 2 and 3 processes: the same as one process",
          "[mpi][osb]") {
  // No squares, so no lattice sweep: every bond on the lists, whose
  // dilatation pass and force pass are separate loops with the exchange
  // between them (force_field.cpp). A coarser plate (about 3,400 particles,
  // delta = 2.5 mm), as the lists are slower.
  const Case c = make_case("osb_lists", "osb", "--grid free --spacing 0.625mm --horizon 2.5mm");
  const std::string out2 = c.folder + "/run2", out3 = c.folder + "/run3";
  REQUIRE(run_on_processes(c, 2, out2) == 0);
  REQUIRE(run_on_processes(c, 3, out3) == 0);
  const Reference reference = one_process_reference(c);
  CHECK(reference.lattice_particles == 0);
  check_against_reference(out2, reference);
  check_against_reference(out3, reference);
}

TEST_CASE("an OSB run on 2 processes restarted on 3 ends as the uninterrupted 2-process run", "[mpi][osb][restart]") {
  check_restart_on_other_process_count(make_case("osb_restart", "osb"));
}

TEST_CASE("a quasi-static scene on 2 processes is refused, naming its table", "[mpi]") {
  Case c = make_case("quasi_static");
  // The same plate pulled quasi-statically (the one-process solver runs this scene).
  c.scene = c.folder + "/c3a_quasi_static.toml";
  std::ofstream(c.scene) << "particles = \"c3a.pdp\"\n"
                         << "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\nthickness = 1.0\n"
                            "plane = \"stress\"\n"
                         << "[quasi_static]\nload_factors = [1.0]\n"
                         << "[[loads]]\nset = \"top\"\ntype = \"displacement\"\ny = 1e-6\n"
                         << "[[loads]]\nset = \"bottom\"\ntype = \"fixed\"\n";
  const std::string out = c.folder + "/qs";
  CHECK(run_on_processes(c, 2, out) != 0);
  const std::string log = file_text(out + ".log");
  CHECK(log.find("table [quasi_static]") != std::string::npos);
  CHECK(log.find("one process") != std::string::npos);
  // Both processes refuse it; the root alone says so (docs/solver.md, "Errors on several processes").
  CHECK(occurrences(log, "pd-solve: error:") == 1);
}

TEST_CASE("a bad scene key or a missing particle file on 2 processes is reported once, with a non-zero exit", "[mpi]") {
  // Every process reads the scene and raises the same error, before any
  // particle file is read (none exists here): the root prints it, alone.
  Case c;
  c.folder = case_folder("bad_key");
  c.scene = c.folder + "/bad_key.toml";
  std::ofstream(c.scene) << "particles = \"absent.pdp\"\n"
                         << "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
                         << "[model]\ntype = \"osb\"\nfailure_variant = \"all\"\n";
  const std::string out = c.folder + "/run";
  CHECK(run_on_processes(c, 2, out) != 0);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "unknown key 'model.failure_variant' = 'all'") == 1);
  CHECK(occurrences(log, "pd-solve: error:") == 1);
  CHECK(occurrences(log, "process 1 of 2") == 0);

  // The scene without the bad key: every process fails to open the particle file, the root says so.
  std::ofstream(c.scene) << "particles = \"absent.pdp\"\n"
                         << "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
                         << "poisson_ratio = 0.35\n[model]\ntype = \"osb\"\n[time]\nend = 1e-6\nstep = \"auto\"\n";
  const std::string out_absent = c.folder + "/absent";
  CHECK(run_on_processes(c, 2, out_absent) != 0);
  const std::string absent_log = file_text(out_absent + ".log");
  INFO(absent_log);
  CHECK(occurrences(absent_log, "absent.pdp\": no such file") == 1);
  CHECK(occurrences(absent_log, "pd-solve: error:") == 1);
}

TEST_CASE("pd-solve prints its --version and --help once on 2 processes", "[mpi]") {
  // Every process parses the command line; the root alone prints what was asked for.
  const std::string folder = case_folder("version_once");
  for (const std::string option : {"--version", "--help"}) {
    const std::string log = folder + "/" + option.substr(2) + ".log";
    std::ostringstream command;
    command << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " 2 " << PD_MPIEXEC_PREFLAGS << " \""
            << PD_SOLVE_EXECUTABLE << "\" " << option << " > \"" << log << "\" 2>&1";
    CHECK(run_shell(command.str()) == 0);
    const std::string text = file_text(log);
    INFO(text);
    CHECK(occurrences(text, option == "--version" ? "pd-solve " : "--restart") == 1);
  }
}

TEST_CASE("a non-finite value in one process's slab is reported by that process alone, with its rank", "[mpi]") {
  // An absurd initial velocity on the left edge, which process 0's slab
  // holds: its particles' forces overflow in the first step, far from the
  // cut, so only process 0 has a non-finite value; the others stop with it,
  // silently (docs/solver.md, "Errors on several processes").
  const Case c = make_case("non_finite", "osb", "--grid free --spacing 0.625mm --horizon 2.5mm");
  std::ofstream(c.scene, std::ios::app) << "[[loads]]\nset = \"left\"\ntype = \"initial_velocity\"\nx = -1e300\n";
  const std::string out = c.folder + "/run";
  CHECK(run_on_processes(c, 2, out, "--set time.end=2e-6") != 0);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "pd-solve: error:") == 1);
  CHECK(log.find("pd-solve: error: process 0 of 2: the run became unstable at step 1") != std::string::npos);
  CHECK(log.find("non-finite velocity of particle") != std::string::npos);
}

// Variable horizons (theory.md Sec. 6) on several processes: C3-A at
// dx = 0.625 mm, delta = 2.5 mm (m = 4) with its boxes round the pores meshed
// at dx / 2 (pd-mesh --box-spacing; horizons 1.25 mm in the boxes), 5,784
// particles, pulled twice as fast (3 m/s over 10 us, 22 us: the crack runs
// from about 15 us, and the edges break up after 20 us). Several processes
// run ordinary PD on the rows of each slab's band, cut to the slab
// (setup/local_bonds.hpp, local_rows; no lattice sweep), so its reference is
// one process on the same rows (SetupOptions::lattice_kernel off; the rows
// are checked against the physics and the lattice split in
// tests/solver/test_dual_horizon*.cpp). Dual-horizon PMB (since 7 December
// 2026) and OSB (since 8 December 2026) take the lattice split on the
// slabs: their reference is one process with the lattice sweep, as pd-solve
// runs it.
// An owned particle's row is the one-process row, entry for entry, and its
// dual entries (the reactions of bonds other particles own towards it, up
// to the largest horizon away) read ghosts that arrive bit for bit, so the
// same tolerances as above hold: both copies of a bond break at the same
// step wherever they live.
namespace {
const std::string box_grid = "--spacing 0.625mm --horizon 2.5mm --box-spacing 0.3125mm";
const Loading fast{3.0, 1e-5, 22e-6};

// The particle file's smallest and largest horizon [m].
std::pair<double, double> horizon_range(const Case& c) {
  const pd::ParticleSet p = pd::read_particle_file(c.particles);
  const auto [low, high] = std::minmax_element(p.horizon.begin(), p.horizon.end());
  return {*low, *high};
}

// The scene on 2 and 3 processes against one process on the rows. Each
// process makes its set-up on its slab's band (before 7 December 2026 on
// the whole plate: "model.dual_horizon = true: the rows reach up to the
// largest horizon", "the particle file's horizons differ"), which the plan
// and summary.json name, and reports the one-process counts and stable step.
// `lattice_split`: dual horizons, whose squares at the stencil's horizon
// go through the lattice sweep on every process count (summary.json's
// lattice_particles the one-process count).
void check_variable_horizons_on_several_processes(const Case& c, bool lattice_split = false) {
  const auto [smallest, largest] = horizon_range(c);
  CHECK(smallest == Approx(1.25e-3).epsilon(1e-9));
  CHECK(largest == Approx(2.5e-3).epsilon(1e-9));
  const std::string out2 = c.folder + "/run2", out3 = c.folder + "/run3";
  REQUIRE(run_on_processes(c, 2, out2) == 0);
  REQUIRE(run_on_processes(c, 3, out3) == 0);
  const Reference reference = one_process_reference(c, lattice_split);
  if (lattice_split)
    CHECK(reference.lattice_particles > 100);  // (864 of 5,784 particles with the boxes, 204 with the smoothed horizon)
  else
    CHECK(reference.lattice_particles == 0);
  // A coarse plate and a short run: fewer particles reach damage 0.35 than on
  // the finer plate above (22 with ordinary PD), thousands of bonds break.
  check_against_reference(out2, reference, 15);
  check_against_reference(out3, reference, 15);
  CHECK(reference.rows.back()[6] > 2000);
  for (const std::string& out : {out2, out3}) {
    INFO(out);
    CHECK(file_text(out + ".log").find("set-up:    on each process's slab's band of the particle file") !=
          std::string::npos);
    const std::string summary = file_text(out + "/summary.json");
    CHECK(summary.find("\"setup\": \"slab band\"") != std::string::npos);
    CHECK(summary.find("\"setup_whole_plate_reason\": \"\"") != std::string::npos);
    CHECK(summary_number(summary, "setup_particles_read_max") < static_cast<double>(reference.particles));
    CHECK(summary_number(summary, "particles") == static_cast<double>(reference.particles));
    CHECK(summary_number(summary, "directed_bonds") == static_cast<double>(reference.directed_bonds));
    CHECK(summary_number(summary, "precrack_bonds_cut") == static_cast<double>(reference.precrack_bonds_cut));
    CHECK(summary_number(summary, "lattice_particles") == static_cast<double>(reference.lattice_particles));
    CHECK(reference.precrack_bonds_cut > 0);
    // The plate's stable limit (the smallest over the processes' owned rows), not the root's band's.
    // (summary.json's 12 digits.)
    CHECK(summary_number(summary, "stable_time_step_s") == Approx(reference.stable_time_step).epsilon(1e-11));
  }
}
}  // namespace

TEST_CASE("dual-horizon PMB with finer boxes on 2 and 3 processes: the damage and displacements of one process",
          "[mpi][dual_horizon]") {
  const Case c = make_case("dual_pmb", "pmb", box_grid, "true", fast);
  check_variable_horizons_on_several_processes(c, /*lattice_split=*/true);
  // The plan says how many particles the sweep takes, as on one process
  // (before 7 December 2026: "dual-horizon rows for all 5784 particles
  // (several processes run dual horizons on the rows alone)").
  const std::string log = file_text(c.folder + "/run2.log");
  CHECK(log.find("  kernel:    lattice sweep for ") != std::string::npos);
  CHECK(log.find(" particles (squares at the stencil's horizon), dual-horizon rows for ") != std::string::npos);
  CHECK(log.find("dual-horizon rows for all") == std::string::npos);
  CHECK(log.find("on 2 processes") != std::string::npos);
}

TEST_CASE("dual-horizon OSB with finer boxes on 2 and 3 processes: the damage and displacements of one process",
          "[mpi][dual_horizon][osb]") {
  // A dual entry's force reads its owner's theta / m: for an owner on
  // another process it arrives with the second exchange of the step.
  // Its squares at the stencil's horizon go through the lattice sweep on
  // each slab, as on one process (since 8 December 2026; before, every bond
  // on the rows: "dual-horizon rows for all 5784 particles (several
  // processes run dual-horizon OSB on the rows alone)", results those of one
  // process with the lattice off, off the default run by the sweep's
  // round-off).
  const Case c = make_case("dual_osb", "osb", box_grid, "true", fast);
  check_variable_horizons_on_several_processes(c, /*lattice_split=*/true);
  const std::string summary = file_text(c.folder + "/run2/summary.json");
  CHECK(summary.find("\"ghost_exchanges_per_step\": 2") != std::string::npos);
  for (const std::string run : {"run2", "run3"}) {
    INFO(run);
    const std::string log = file_text(c.folder + "/" + run + ".log");
    CHECK(log.find("  kernel:    lattice sweep for 864 particles (squares at the stencil's horizon), dual-horizon "
                   "rows for 4920") != std::string::npos);
    CHECK(log.find("dual-horizon rows for all") == std::string::npos);
  }
}

// A smoothed horizon (theory.md Sec. 7): the refined squares' horizon ramps
// from 1.25 to 2.5 mm over 2 mm at the region's edges, and both slab cuts
// of 3 processes cross the region, so that the owners of bonds towards a
// slab have many horizons.
TEST_CASE("dual-horizon PMB with a smoothed horizon on 2 and 3 processes: set up on each slab's band, the damage and "
          "displacements of one process",
          "[mpi][dual_horizon][band]") {
  check_variable_horizons_on_several_processes(
      make_case("dual_smoothed", "pmb",
                "--spacing 0.625mm --horizon 2.5mm --refine-region 10mm,5mm,40mm,20mm --refine-factor 2 "
                "--horizon-smoothing 2mm",
                "true", fast),
      /*lattice_split=*/true);
}

TEST_CASE("ordinary PMB with variable horizons on 2 and 3 processes: the same as one process",
          "[mpi][dual_horizon]") {
  check_variable_horizons_on_several_processes(make_case("ordinary_variable", "pmb", box_grid, "false", fast));
}

// The checkpoint holds each bond's state once, in its owner's family; a
// dual entry (and a combined entry's reverse) takes it from there, also when
// its owner is on another process after the restart. Stopped at 17.6 us,
// restarted from step 80, when the crack has broken about 300 bonds (one
// process: 736 directed bonds broken at step 80, 412 of them by the
// pre-crack).
namespace {
void check_dual_horizon_restart(const std::string& name, const std::string& model) {
  const Case c = make_case(name, model, box_grid, "true", fast);
  check_restart_on_other_process_count(c, 20, 0.8);
  const auto rows = energy_rows(c.folder + "/parts_2_3");
  REQUIRE(rows.size() > 1);
  CHECK(rows.back()[6] > 2000);  // broken bonds at the end: the crack ran on after the restart
}
}  // namespace

TEST_CASE("a dual-horizon run on 2 processes restarted on 3 ends as the uninterrupted 2-process run",
          "[mpi][dual_horizon][restart]") {
  check_dual_horizon_restart("dual_restart", "pmb");
}

// Between one process and several: one process's general rows of the
// lattice split hold the dual entries of the bonds between general
// particles; placing a checkpoint of several, each takes its owner's bond's
// state from the row of its owner, and the root's one-process set-up turns
// a one-process checkpoint family by family (since 8 December 2026; before,
// refused by the key).
// Dual-horizon OSB too: since both counts take the lattice split, its runs on
// one process and on several agree bit for bit, and so do its restarts.
TEST_CASE("a dual-horizon PMB or OSB run restarted from one process on 2, and from 2 on one, ends as the uninterrupted run",
          "[mpi][dual_horizon][restart]") {
  for (const char* model : {"pmb", "osb"}) {
    INFO("model.type = " << model);
    const Case c = make_case(std::string("dual_restart_1_2_") + model, model, box_grid, "true", fast);
    check_restart_on_other_process_count(c, 20, 0.8, 1, 2);
    check_restart_on_other_process_count(c, 20, 0.8, 2, 1);
    const auto rows = energy_rows(c.folder + "/parts_2_1");
    REQUIRE(rows.size() > 1);
    CHECK(rows.back()[6] > 2000);  // broken bonds at the end: the crack ran on after the restart
  }
}

// The same with dual-horizon OSB (no combined entries: every dual entry
// names its owner's bond by the particle file's numbers, which a band's rows
// take from the file's family offsets).
TEST_CASE("a dual-horizon OSB run on 2 processes restarted on 3 ends as the uninterrupted 2-process run",
          "[mpi][dual_horizon][restart][osb]") {
  check_dual_horizon_restart("dual_osb_restart", "osb");
}

// The distributed set-up on the slabs' bands (docs/solver.md, "Set-up"):
// with PMB and one horizon each process reads only the particles within
// three bond reaches of its slab and makes the set-up on them. The same
// plate as above with more of what a set-up resolves on the whole plate: a
// pin (the particle nearest to a point, in the last slab), a traction on
// the left edge (its body force from the whole set's area) and a stop
// region the crack reaches at 42 us (247 of the 265 steps). Reference: the
// same scene on one process, run by pd-solve itself (its set-up is the
// whole plate's); the runs must agree as the tests above require, stop at
// the same step, and report the one-process counts (summed over the
// processes from their owned particles).
namespace {
// A number field of a run folder's summary.json (the first with this name), which must be there.
double summary_field(const std::string& out, const std::string& name) {
  const double value = summary_number(file_text(out + "/summary.json"), name);
  REQUIRE(!std::isnan(value));
  return value;
}

// `c` with a pin, a traction and a stop region (above) on 2 and 3
// processes: each makes its set-up on its slab's band, which the plan and
// summary.json name, and the runs end as the one-process run of pd-solve.
// `load_lines`: the plan's lines of the pin and the traction on this plate;
// `stop_box`: the stop region, where the crack reaches damage 0.35 before the end.
void check_band_setup_against_one_process(
    const Case& c,
    const std::vector<std::string>& load_lines = {"load2: fixed on the particle nearest to [0.05, 0.0125] (1 particles)",
                                                  "left: traction on set 'left' (320 particles), edge length 0.025 m"},
    const std::string& stop_box = "[0.006, 0.010, 0.012, 0.015]") {
  std::ofstream(c.scene, std::ios::app)
      << "[[loads]]\nnearest = [0.05, 0.0125]\ntype = \"fixed\"\n"
      << "[[loads]]\nset = \"left\"\ntype = \"traction\"\nx = -2e5\nramp_time = 2e-5\n"
      << "[stop]\nbox = " << stop_box << "\ndamage = 0.35\n";
  const std::string one = c.folder + "/run1";
  REQUIRE(run_on_processes(c, 1, one) == 0);
  const auto reference_rows = energy_rows(one);
  const std::string reference_stop = file_text(one + "/summary.json");
  REQUIRE(reference_stop.find("\"stop_reason\": \"stop condition") != std::string::npos);
  const double steps = summary_field(one, "steps");
  CHECK(steps < std::floor(c.end_time / summary_field(one, "time_step_s")));  // stopped before the end time
  // The surface correction's iterations as the plan gives them (its effects line).
  const auto effects_line = [](const std::string& log) {
    const auto at = log.find("  effects:");
    return at == std::string::npos ? std::string() : log.substr(at, log.find('\n', at) - at);
  };
  const std::string one_effects = effects_line(file_text(one + ".log"));
  CHECK(one_effects.find(c.surface_correction ? " iterations)" : "surface correction off") != std::string::npos);
  const auto damage = vtp_array(one + "/arrival.vtp", "damage");
  CHECK(std::count_if(damage.begin(), damage.end(), [](double d) { return d >= 0.35; }) > 20);
  for (int processes : {2, 3}) {
    INFO(processes << " processes");
    const std::string out = c.folder + "/run" + std::to_string(processes);
    REQUIRE(run_on_processes(c, processes, out) == 0);
    const std::string log = file_text(out + ".log");
    CHECK(log.find("set-up:    on each process's slab's band of the particle file") != std::string::npos);
    CHECK(file_text(out + "/summary.json").find("\"setup\": \"slab band\"") != std::string::npos);
    CHECK(effects_line(log) == one_effects);
    // A band is its slab and three bond reaches on each inner side: less than the plate.
    const double particles = summary_field(out, "particles");
    CHECK(summary_field(out, "setup_particles_read_max") < particles);
    for (const std::string count :
         {"particles", "directed_bonds", "precrack_bonds_cut", "lattice_particles", "steps", "pieces"})
      CHECK(summary_field(out, count) == summary_field(one, count));
    // The plate's stable limit (the smallest over the processes), not the root's own.
    CHECK(summary_field(out, "stable_time_step_s") == Approx(summary_field(one, "stable_time_step_s")).epsilon(1e-12));
    CHECK(summary_field(out, "precrack_bonds_cut") > 0);
    // The loads' particle counts and the traction's edge length of the whole plate.
    for (const std::string& line : load_lines) CHECK(log.find(line) != std::string::npos);
    for (const std::string array : {"damage", "displacement", "arrival_time_0.35"})
      CHECK(vtp_array(out + "/arrival.vtp", array) == vtp_array(one + "/arrival.vtp", array));
    // The stop reason names the same particle on every partition.
    const auto stop_reason = [](const std::string& summary) {
      const auto at = summary.find("\"stop_reason\": \"");
      return at == std::string::npos ? std::string() : summary.substr(at, summary.find('"', at + 16) - at);
    };
    CHECK(stop_reason(file_text(out + "/summary.json")) == stop_reason(reference_stop));
    const auto rows = energy_rows(out);
    REQUIRE(rows.size() == reference_rows.size());
    double scale = 0;
    for (const auto& r : reference_rows) scale = std::max({scale, std::fabs(r[2]), std::fabs(r[3]), std::fabs(r[4])});
    for (std::size_t m = 0; m < rows.size(); ++m) {
      INFO("energy row " << m);
      REQUIRE(rows[m].size() == reference_rows[m].size());
      CHECK(rows[m][1] == reference_rows[m][1]);  // step
      CHECK(rows[m][6] == reference_rows[m][6]);  // broken bonds, exactly
      for (std::size_t column = 2; column < rows[m].size(); ++column)
        if (column != 6)  // (reactions [N] are far larger than the energies [J])
          CHECK(std::fabs(rows[m][column] - reference_rows[m][column]) <=
                1e-8 * scale + 1e-12 * std::fabs(reference_rows[m][column]));
    }
  }
}
}  // namespace

TEST_CASE("PMB on 2 and 3 processes makes its set-up on each slab's band: named in the plan and summary, and the "
          "one-process run's counts, loads, stop and results",
          "[mpi][band]") {
  check_band_setup_against_one_process(make_case("band"));
}

// The state-based model's set-up on the bands: its distortion factors from
// each particle's own family, its dilatation factors iterated on the slabs
// (the ghosts' from their owners every iteration), its stable step with a
// ghost's g_j / m_j^2 from the owner.
TEST_CASE("OSB with the surface correction on 2 and 3 processes makes its set-up on each slab's band: the "
          "one-process run's counts, iterations, loads, stop and results",
          "[mpi][band][osb]") {
  check_band_setup_against_one_process(make_case("band_osb", "osb"));
}

TEST_CASE("OSB without the surface correction on 2 and 3 processes makes its set-up on each slab's band: the "
          "one-process run's counts, loads, stop and results",
          "[mpi][band][osb]") {
  Case c = make_case("band_osb_plain", "osb");
  set_surface_correction(c, false);
  check_band_setup_against_one_process(c);
}

// A file whose horizons differ, run as ordinary PD (which one process runs
// on the same rows as several: no lattice sweep): the bands' rows give the
// one-process run's results, counts, loads and stop step bit for bit. On
// this coarse plate the damage grows first along the boxes' edges, where the
// horizon changes (ordinary PD's ghost forces): the stop region lies on the
// upper one, which reaches damage 0.35 there at step 198 of 213.
TEST_CASE("ordinary PMB on horizons that differ makes its set-up on each slab's band on 2 and 3 processes: the "
          "one-process counts, loads, stop and results",
          "[mpi][band][dual_horizon]") {
  const Case c = make_case("band_ordinary_variable", "pmb", box_grid, "false");
  check_band_setup_against_one_process(c,
                                       {"load2: fixed on the particle nearest to [0.05, 0.0125] (1 particles)",
                                        "left: traction on set 'left' (196 particles), edge length 0.025 m"},
                                       "[0.012, 0.016, 0.018, 0.019]");
}

// Dual-horizon PMB on the same plate: its squares at the stencil's horizon
// go through the lattice sweep on each slab as on one process (since 7
// December 2026; before, several processes ran every bond on the rows,
// whose results differ from the one-process run by the sweep's float
// round-off), so the one-process run of pd-solve is the reference bit for
// bit. The stop region lies on the pre-crack's line, which the crack
// reaches at step 194 of 214.
TEST_CASE("dual-horizon PMB on 2 and 3 processes takes the lattice split on each slab's band: the one-process "
          "lattice particles, counts, loads, stop and results",
          "[mpi][band][dual_horizon]") {
  const Case c = make_case("band_dual", "pmb", box_grid, "true");
  check_band_setup_against_one_process(c,
                                       {"load2: fixed on the particle nearest to [0.05, 0.0125] (1 particles)",
                                        "left: traction on set 'left' (196 particles), edge length 0.025 m"},
                                       "[0.006, 0.011, 0.008, 0.014]");
  CHECK(summary_field(c.folder + "/run1", "lattice_particles") > 500);
}

// Dual-horizon OSB on the same plate, with the pin, traction and stop
// region: its squares at the stencil's horizon go through the lattice sweep
// on each slab (since 8 December 2026; before, several processes ran every
// bond on the rows, the plan said "dual-horizon rows for all ... (several
// processes run dual-horizon OSB on the rows alone)", and the results were
// off the one-process run of pd-solve by the sweep's float round-off), so
// that run is the reference bit for bit; each process's slab holds lattice
// particles of its own.
TEST_CASE("dual-horizon OSB on 2 and 3 processes sweeps the lattice on each slab: the one-process lattice count, "
          "loads, stop and results",
          "[mpi][band][dual_horizon][osb]") {
  const Case c = make_case("band_dual_osb", "osb", box_grid, "true");
  check_band_setup_against_one_process(c,
                                       {"load2: fixed on the particle nearest to [0.05, 0.0125] (1 particles)",
                                        "left: traction on set 'left' (196 particles), edge length 0.025 m"},
                                       "[0.006, 0.011, 0.008, 0.014]");
  const double lattice = summary_field(c.folder + "/run1", "lattice_particles");
  CHECK(lattice > 500);
  for (const std::string run : {"run2", "run3"}) {
    INFO(run);
    CHECK(summary_field(c.folder + "/" + run, "lattice_particles") == lattice);
    CHECK(file_text(c.folder + "/" + run + ".log")
              .find("  kernel:    lattice sweep for " + std::to_string(static_cast<long>(lattice)) +
                    " particles (squares at the stencil's horizon)") != std::string::npos);
  }
}

TEST_CASE("a pre-crack that cuts no bond is refused once on 2 processes with band set-ups", "[mpi][band]") {
  // The second crack lies outside the plate: no band has a bond it cuts, so
  // the sum over the processes is 0 and every process refuses the scene.
  const Case c = make_case("band_precrack");
  std::ofstream(c.scene, std::ios::app) << "[[precracks]]\nfrom = [0.06, 0.03]\nto = [0.07, 0.03]\n";
  const std::string out = c.folder + "/run2";
  CHECK(run_on_processes(c, 2, out) != 0);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "precracks[1] from [0.06, 0.03] to [0.07, 0.03] m cuts no bond") == 1);
  CHECK(occurrences(log, "pd-solve: error:") == 1);
}

TEST_CASE("a pre-crack that cuts the plate apart is found on 2 processes with band set-ups (no band sees the "
          "whole cut)",
          "[mpi][band]") {
  // The pre-crack runs on across the plate (50 mm wide) at mid-height: two
  // pieces (docs/robustness.md), which one process finds on the whole
  // plate's set-up and several processes together.
  const Case c = make_case("band_cut_apart");
  std::ofstream(c.scene, std::ios::app) << "[[precracks]]\nfrom = [0.002, 0.0125]\nto = [0.05, 0.0125]\n";
  const std::string one = c.folder + "/run1", two = c.folder + "/run2";
  REQUIRE(run_on_processes(c, 1, one, "--set time.end=1e-6") == 0);
  REQUIRE(run_on_processes(c, 2, two, "--set time.end=1e-6") == 0);
  CHECK(summary_field(one, "pieces") == 2);
  CHECK(summary_field(two, "pieces") == 2);
  const std::string summary = file_text(two + "/summary.json");
  INFO(summary);
  CHECK(summary.find("the pre-cracks cut the plate into 2 pieces") != std::string::npos);
  // The same warning, with the same piece sizes, as on one process.
  const auto warning = [](const std::string& text) {
    const auto at = text.find("the pre-cracks cut the plate into");
    return at == std::string::npos ? std::string() : text.substr(at, text.find('"', at) - at);
  };
  CHECK(warning(summary) == warning(file_text(one + "/summary.json")));
  // Into one place (stdout and stderr of mpirun into one file) the warning
  // comes once, as on one process (before 5 December 2026 twice: the plan's
  // line and its echo on stderr, since each process's streams are pipes).
  CHECK(occurrences(file_text(two + ".log"), "the pre-cracks cut the plate into") == 1);
  // With stdout elsewhere it is echoed on stderr.
  const std::string apart = c.folder + "/apart";
  std::ostringstream command;
  command << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " 2 " << PD_MPIEXEC_PREFLAGS << " \""
          << PD_SOLVE_EXECUTABLE << "\" \"" << c.scene << "\" --threads 1 -q -o \"" << apart
          << "\" --set time.end=1e-6 > \"" << apart << ".out\" 2> \"" << apart << ".err\"";
  REQUIRE(run_shell(command.str()) == 0);
  CHECK(occurrences(file_text(apart + ".err"), "pd-solve: warning: the pre-cracks cut the plate into") == 1);
}

TEST_CASE("a time step above the stable limit is refused once on 2 processes", "[mpi]") {
  const Case c = make_case("step_too_large");
  const std::string out = c.folder + "/run2";
  CHECK(run_on_processes(c, 2, out, "--set time.step=1e-6") == 1);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "key 'time.step' = 1e-06 s is above the stable limit") == 1);
  check_said_once_by_the_root(log);
}

// Ctrl-C at mpirun: it sends SIGTERM to every process, which each see it at
// their own step. They agree on it, finish one step together, write its
// checkpoint, and say so once; --restart then ends as the uninterrupted run.
// (docs/solver.md, "Interrupting a run".) Open MPI 4 sends SIGTERM
// odls_base_sigkill_timeout seconds after the Ctrl-C and SIGKILL as long
// after that, and mpirun ends after both: its default of 1 s, which a loaded
// machine overran once before the message came, is 4 s here (the run takes
// about 6 s longer to end, not 30 s as a longer grace would). The signal
// comes once the run is in its time loop (its checkpoint of step 100 written).
TEST_CASE("Ctrl-C at mpirun ends a 2-process run with a checkpoint of its step, from which --restart goes on",
          "[mpi][restart]") {
  const Case c = make_case("interrupted");
  const std::string whole = c.folder + "/whole", parts = c.folder + "/parts";
  const std::string checkpoints = " --set output.checkpoint_interval=100";
  // The run to an end it never reaches here, interrupted after its first checkpoint.
  std::ostringstream command;
  command << "exec " << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " 2 " << PD_MPIEXEC_PREFLAGS
          << " --mca odls_base_sigkill_timeout 4 \"" << PD_SOLVE_EXECUTABLE << "\" \"" << c.scene
          << "\" --threads 1 -o \"" << parts << "\"" << checkpoints << " --set time.end=1";
  const pid_t child = pd::test_support::start_process({"/bin/sh", "-c", command.str()}, parts + ".log");
  REQUIRE(child >= 0);
  for (int wait = 0; wait < 12000 && !fs::exists(parts + "/checkpoint.bin"); ++wait) ::usleep(10000);
  REQUIRE(fs::exists(parts + "/checkpoint.bin"));
  const int status = pd::test_support::interrupt_and_wait(child, SIGINT);
  const std::string log = file_text(parts + ".log");
  INFO(log);
  CHECK(status > 0);  // an exit status of its own, not killed by the signal
  CHECK(occurrences(log, "pd-solve: error: interrupted by SIGTERM at step ") == 1);
  CHECK(occurrences(log, "pd-solve: error:") == 1);
  CHECK(occurrences(log, "MPI_ABORT") == 0);
  CHECK_FALSE(fs::exists(parts + "/summary.json"));
  const std::string said = "interrupted by SIGTERM at step ";
  REQUIRE(log.find(said) != std::string::npos);
  const long step = std::stol(log.substr(log.find(said) + said.size()));
  CHECK(step >= 100);
  // Restarted to a nearer end (only time.end may change), against the run
  // to that end uninterrupted: the same damage and displacements.
  const double time = std::stod(log.substr(log.find("(t = ", log.find(said)) + 5));
  char end[80];
  std::snprintf(end, sizeof end, " --set time.end=%.17g", time * 1.02);
  REQUIRE(run_on_processes(c, 2, whole, checkpoints + end) == 0);
  REQUIRE(run_on_processes(c, 2, parts, checkpoints + end + " --restart") == 0);
  CHECK_THAT(file_text(parts + ".log"), Catch::Contains("steps:     " + std::to_string(step) + " -> "));
  for (const std::string array : {"damage", "displacement"})
    CHECK(vtp_array(whole + "/arrival.vtp", array) == vtp_array(parts + "/arrival.vtp", array));
}

// The root alone takes the output folder's lock (docs/solver.md, "Output
// folders"): its refusal concerns the whole run, so it carries no rank.
TEST_CASE("a 2-process run into a folder another run writes is refused once, without a rank", "[mpi]") {
  const Case c = make_case("locked");
  const std::string out = c.folder + "/run";
  const pid_t first = pd::test_support::start_process(
      {PD_SOLVE_EXECUTABLE, c.scene, "--threads", "1", "-o", out, "--set", "time.end=1", "--set",
       "output.checkpoint_interval=100"},
      c.folder + "/first.log");
  REQUIRE(first >= 0);
  for (int wait = 0; wait < 12000 && !fs::exists(out + "/checkpoint.bin"); ++wait) ::usleep(10000);
  const bool started = fs::exists(out + "/checkpoint.bin");
  const int second = run_on_processes(c, 2, out);
  ::kill(first, SIGTERM);
  int status = 0;
  ::waitpid(first, &status, 0);
  REQUIRE(started);
  CHECK(second != 0);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "another pd-solve run (PID " + std::to_string(first) + ") is writing into this folder") == 1);
  CHECK(occurrences(log, "pd-solve: error:") == 1);
  CHECK(occurrences(log, "process 0 of 2") == 0);
  CHECK(occurrences(log, "MPI_ABORT") == 0);
}

// A small plate for the checks of input and messages: the plate of
// geometries/plate_no_pores.geo (50 mm x 25 mm) at dx = 1 mm, delta = 4 mm
// (1,250 particles), its top and bottom edges pulled apart for 2 us (4 steps).
Case make_small_case(const std::string& name) {
  Case c;
  c.end_time = 2e-6;
  c.folder = case_folder(name);
  c.particles = c.folder + "/plate.pdp";
  REQUIRE(run_shell(std::string("\"") + PD_MESH_EXECUTABLE + "\" \"" + PD_GEOMETRY_DIR +
                    "/plate_no_pores.geo\" --spacing 1mm --horizon 4mm -o \"" + c.particles + "\" > \"" + c.folder +
                    "/mesh.log\" 2>&1") == 0);
  c.scene = c.folder + "/plate.toml";
  std::ofstream(c.scene) << "particles = \"plate.pdp\"\n"
                         << "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
                            "poisson_ratio = 0.35\n"
                         << "[time]\nstep = \"auto\"\nend = 2e-6\n"
                         << "[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = 1.5\n"
                         << "[[loads]]\nset = \"bottom\"\ntype = \"velocity\"\ny = -1.5\n"
                         << "[output]\nenergy_interval = 2\n";
  return c;
}

// pd-solve on `processes` processes (`launcher`: more of mpiexec's options)
// with `arguments`, stdout and stderr into `out`.log, stopped after 60 s
// (a hang fails the test, exit status 124, instead of stalling the suite).
int run_within_a_minute(const Case& c, int processes, const std::string& launcher, const std::string& out,
                        const std::string& arguments) {
  std::ostringstream command;
  command << "timeout 60 " << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " " << processes << " "
          << PD_MPIEXEC_PREFLAGS << " " << launcher << " \"" << PD_SOLVE_EXECUTABLE << "\" \"" << c.scene
          << "\" -q -o \"" << out << "\" " << arguments << " > \"" << out << ".log\" 2>&1";
  return run_shell(command.str());
}

// Two processes of two (or 99) threads on a machine of fewer than four
// (198) hardware threads would take turns on its processors: each is capped
// to its share, said once, by the root (docs/scenes.md, --threads). Not
// bound to cores (--bind-to none), so that the share alone caps them.
TEST_CASE("threads beyond each process's share of the machine are capped, said once", "[mpi][threads]") {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  if (pd::test_support::processors_allowed() < hardware) {
    WARN("bound to fewer hardware threads than the machine has (taskset, a container's CPU set): the binding caps");
    return;
  }
  const Case c = make_small_case("threads");
  const int share = std::max(1, hardware / 2);
  for (const int threads : {2, 99}) {
    INFO("--threads " << threads);
    const std::string out = c.folder + "/run" + std::to_string(threads);
    REQUIRE(run_within_a_minute(c, 2, "--bind-to none", out, "--threads " + std::to_string(threads)) == 0);
    const std::string log = file_text(out + ".log");
    INFO(log);
    if (share < threads) {
      CHECK(occurrences(log, "pd-solve: note: --threads " + std::to_string(threads) + " is more than each of the 2 "
                             "processes' share (" + std::to_string(share) + ") of the " + std::to_string(hardware) +
                             " hardware threads of this machine; using " + std::to_string(share) + "\n") == 1);
      CHECK(occurrences(log, "pd-solve: note:") == 1);
    } else {
      CHECK(occurrences(log, "pd-solve: note: --threads") == 0);
    }
    const int used = std::min(threads, share);
    CHECK(file_text(out + "/summary.json").find("\"threads\": " + std::to_string(used) + ",") != std::string::npos);
    CHECK(occurrences(log, "pd-solve: error:") == 0);
  }
}

// The processes on this machine are counted by MPI itself (the processes
// that share its memory), not from Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE,
// which another MPI's launcher (MPICH's Hydra) does not set: here each
// process starts without it, and the share is still half the machine
// (before 7 December 2026 each process counted itself alone and took every
// hardware thread).
TEST_CASE("the processes on this machine are counted without Open MPI's variable for them", "[mpi][threads]") {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  if (pd::test_support::processors_allowed() < hardware || hardware < 2) {
    WARN("bound to fewer hardware threads than the machine has, or one hardware thread: no share to see");
    return;
  }
  const Case c = make_small_case("local_processes");
  const int share = hardware / 2;
  const std::string out = c.folder + "/run";
  REQUIRE(run_within_a_minute(c, 2, "--bind-to none env -u OMPI_COMM_WORLD_LOCAL_SIZE", out,
                              "--threads " + std::to_string(hardware)) == 0);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "pd-solve: note: --threads " + std::to_string(hardware) + " is more than each of the 2 "
                         "processes' share (" + std::to_string(share) + ") of the " + std::to_string(hardware) +
                         " hardware threads of this machine; using " + std::to_string(share) + "\n") == 1);
  CHECK(file_text(out + "/summary.json").find("\"threads\": " + std::to_string(share) + ",") != std::string::npos);
}

// A process bound to fewer hardware threads than its share (mpirun binds
// each process to a core by default; here to one hardware thread) would run
// its threads in turns on them: capped to them, with a note that says why
// (before 7 December 2026 `mpirun -np 1 --bind-to core pd-solve --threads 2`
// ran 2 threads on one core, without a word).
TEST_CASE("threads beyond the hardware threads a process is bound to are capped to them, said once",
          "[mpi][threads]") {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  if (hardware < 2) {
    WARN("one hardware thread: no binding narrower than the machine");
    return;
  }
  const Case c = make_small_case("bound_threads");
  for (const int processes : {1, 2}) {
    INFO(processes << " processes");
    // One hardware thread each, of a share of hardware / processes.
    const int share = hardware / processes;
    const std::string out = c.folder + "/run" + std::to_string(processes);
    REQUIRE(run_within_a_minute(c, processes, "--bind-to hwthread", out, "--threads 2") == 0);
    const std::string log = file_text(out + ".log");
    INFO(log);
    if (share > 1)
      CHECK(occurrences(log, "pd-solve: note: --threads 2 is more than the 1 of this machine's " +
                                 std::to_string(hardware) + " hardware threads this process is bound to (its CPU "
                                 "affinity: mpirun's --bind-to, taskset); using 1\n") == 1);
    else
      CHECK(occurrences(log, "processes' share (1) of the " + std::to_string(hardware) + " hardware threads") == 1);
    CHECK(occurrences(log, "pd-solve: note:") == 1);
    CHECK(file_text(out + "/summary.json").find("\"threads\": 1,") != std::string::npos);
  }
}

// --threads that is no whole number, under mpirun: every process refuses it,
// the root says so once, and no process waits for another.
TEST_CASE("a thread count that is no whole number is refused once on 2 processes", "[mpi][threads]") {
  const Case c = make_small_case("threads_abc");
  const std::string out = c.folder + "/run";
  CHECK(run_within_a_minute(c, 2, "", out, "--threads abc") == 1);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "pd-solve: error: --threads 'abc': expected a whole number of threads per process") == 1);
  CHECK(occurrences(log, "pd-solve: error:") == 1);
  CHECK(occurrences(log, "MPI_ABORT") == 0);
  CHECK_FALSE(fs::exists(out));
}

// A time.end whose steps no run could take: every process counts the same
// steps and refuses them, the root says so once (before 7 December 2026
// each process said so, with its rank, and MPI_Abort ended the run).
TEST_CASE("a run too long to count is refused once on 2 processes, without a rank", "[mpi]") {
  const Case c = make_small_case("too_long");
  const std::string out = c.folder + "/run";
  CHECK(run_within_a_minute(c, 2, "", out, "--threads 1 --set time.end=1e12") == 1);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(occurrences(log, "pd-solve: error: " + c.scene + ": time.end = 1e+12 s with a time step of ") == 1);
  CHECK(occurrences(log, "refused (shorten time.end, raise time.step") == 1);
  check_said_once_by_the_root(log);
  CHECK_FALSE(fs::exists(out));  // (the run made it, and leaves no folder it made)
}

// Something other than a file where the run writes a result (a folder named
// energy.csv), or a file where it makes snapshots/: refused at the start by
// every process, said once, nothing written (before 7 December 2026 the
// root failed alone when it first wrote there, after the set-up, or after
// the whole run for summary.json, with its rank and MPI_Abort's banner).
TEST_CASE("a folder where a result goes, or a file where the snapshots go, is refused at the start once on 2 "
          "processes",
          "[mpi]") {
  const Case c = make_small_case("result_paths");
  for (const std::string name : {"energy.csv", "arrival.vtp", "summary.json", "snapshots"}) {
    INFO(name);
    const std::string out = c.folder + "/" + name.substr(0, name.find('.'));
    fs::create_directories(out);
    if (name == "snapshots")
      std::ofstream(out + "/" + name) << "a user's notes\n";
    else
      fs::create_directories(out + "/" + name);
    CHECK(run_within_a_minute(c, 2, "", out, "--threads 1 --set output.snapshot_interval=2") == 1);
    const std::string log = file_text(out + ".log");
    INFO(log);
    const std::string said =
        name == "snapshots"
            ? "pd-solve: error: " + out + "/snapshots: not a folder, where the run writes its snapshots (" + c.scene +
                  ", --set: key 'output.snapshot_interval' = 2); move it, or give -o a new or empty folder\n"
            : "pd-solve: error: " + out + "/" + name + ": is a folder, not a file: the result would take its place; "
                  "the run writes its " + name + " there; move it, or give -o a new or empty folder\n";
    CHECK(occurrences(log, said) == 1);
    CHECK(occurrences(log, "pd-solve: error:") == 1);
    CHECK(occurrences(log, "process 0 of 2") == 0);
    CHECK(occurrences(log, "MPI_ABORT") == 0);
    // Refused before the set-up: no result written.
    CHECK_FALSE(fs::is_regular_file(out + "/" + pd::results::energy_file));
    CHECK_FALSE(fs::is_regular_file(out + "/" + pd::results::arrival_file));
  }
}

// A result the root cannot write in the middle of a run (here the snapshot
// folder replaced by a file, or the checkpoint by a folder, once the run has
// written its first one; a full disk alike): every process stops at that
// step, the root says so once, naming the place, what to do and the step, with
// exit status 1 and no MPI_Abort banner; the files written before stay whole
// (before 7 December 2026 the root said it with its rank, "process 0 of 2",
// and MPI_Abort ended the others). The run's end lies far beyond (0.1 s,
// about 170,000 steps): the change comes before it, whenever the test gets
// to it, and the next snapshot or checkpoint meets it.
TEST_CASE("a result the root cannot write during a 2-process run ends every process, said once by the root",
          "[mpi][write_fails]") {
  const Case c = make_small_case("write_fails");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"snapshots", "--set output.snapshot_interval=200"}, {"checkpoint.bin", "--set output.checkpoint_interval=200"}};
  for (const auto& [replaced, outputs] : cases) {
    INFO(replaced);
    const std::string out = c.folder + "/" + replaced.substr(0, replaced.find('.'));
    std::ostringstream command;
    command << "exec timeout 120 " << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " 2 " << PD_MPIEXEC_PREFLAGS
            << " \"" << PD_SOLVE_EXECUTABLE << "\" \"" << c.scene << "\" --threads 1 -q -o \"" << out
            << "\" --set time.end=0.1 " << outputs;
    const pid_t child = pd::test_support::start_process({"/bin/sh", "-c", command.str()}, out + ".log");
    REQUIRE(child >= 0);
    // The first one written (the snapshot of step 0, the checkpoint of step 200) ...
    const std::string first = out + "/" + (replaced == "snapshots" ? "snapshots/step_00000000.vtp" : replaced);
    for (int wait = 0; wait < 6000 && !fs::exists(first); ++wait) ::usleep(10000);
    const bool started = fs::exists(first);
    // ... then its place taken: the folder moved aside and a user's file put
    // there; the checkpoint replaced by a folder (again if the run put a new
    // one there in between).
    const std::string place = out + "/" + replaced;
    if (replaced == "snapshots") {
      fs::rename(place, out + "/snapshots_kept");
      std::ofstream(place) << "a user's notes\n";
    } else {
      std::error_code ignored;
      for (int attempt = 0; attempt < 100 && !fs::is_directory(place); ++attempt) {
        fs::remove(place, ignored);
        fs::create_directory(place, ignored);
      }
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    REQUIRE(started);
    const std::string log = file_text(out + ".log");
    INFO(log);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    // The place named as at the start, with what to do (not "name a file"),
    // then the step.
    const std::string said =
        replaced == "snapshots"
            ? "pd-solve: error: " + place + ": not a folder, where the run writes its snapshots (" + c.scene +
                  ", --set: key 'output.snapshot_interval' = 200); the run stopped at step "
            : "pd-solve: error: " + place + ": is a folder, not a file: the result would take its place; the run "
                  "writes its checkpoint.bin there; the run stopped at step ";
    CHECK(occurrences(log, said) == 1);
    // At a snapshot's or checkpoint's step after the first one the run wrote
    // (200 or later: whenever the place was taken).
    const auto at = log.find(said);
    REQUIRE(at != std::string::npos);
    const long step = std::stol(log.substr(at + said.size()));
    CHECK(step >= (replaced == "snapshots" ? 200 : 400));
    CHECK(step % 200 == 0);
    // One instruction (before 7 December 2026 also the start's "move it, or
    // give -o a new or empty folder", which --restart contradicts).
    CHECK(occurrences(log, replaced == "snapshots" ? " s), its files written before it left whole; run it again with "
                                                     "-o a new folder\n"
                                                   : " s), its files written before it left whole; move it away, then "
                                                     "the same command with --restart goes on from the last "
                                                     "checkpoint\n") == 1);
    CHECK(occurrences(log, "new or empty folder") == 0);
    check_said_once_by_the_root(log);
    // What took the place is as the user left it, and no temporary file is left.
    if (replaced == "snapshots")
      CHECK(file_text(place) == "a user's notes\n");
    else
      CHECK(fs::is_empty(place));
    for (const auto& entry : fs::directory_iterator(out))
      CHECK(entry.path().filename().string().find(".tmp.") == std::string::npos);
    // The files written before are whole: arrival.vtp of the start (or of
    // the first checkpoint), and with checkpoints energy.csv of that step,
    // the header's columns on every row (without, the first energy.csv
    // would have come with the snapshot that failed).
    CHECK(vtp_array(out + "/" + pd::results::arrival_file, "damage").size() == 1250);
    if (replaced == "checkpoint.bin") {
      std::istringstream rows(file_text(out + "/" + pd::results::energy_file));
      std::string header, row;
      REQUIRE(std::getline(rows, header));
      std::size_t count = 0;
      while (std::getline(rows, row)) {
        CHECK(std::count(row.begin(), row.end(), ',') == std::count(header.begin(), header.end(), ','));
        ++count;
      }
      CHECK(count >= 101);  // steps 0, 2, ..., 200 at least
    }
  }
}

// The snapshot folder removed during a run (by hand, to free disk space):
// the next snapshot makes it again, and the root warns once that
// snapshots.pvd lists snapshots whose files are gone (before 7 December 2026
// without a word). The run's end lies far beyond (0.1 s): once the folder is
// back, Ctrl-C at mpirun ends it, and the warning must have come before.
TEST_CASE("a snapshot folder removed during a 2-process run is warned of once, by the root", "[mpi][write_fails]") {
  const Case c = make_small_case("snapshots_removed");
  const std::string out = c.folder + "/run", folder = out + "/snapshots";
  std::ostringstream command;
  command << "exec " << PD_MPIEXEC << " " << PD_MPIEXEC_NUMPROC_FLAG << " 2 " << PD_MPIEXEC_PREFLAGS << " \""
          << PD_SOLVE_EXECUTABLE << "\" \"" << c.scene << "\" --threads 1 -q -o \"" << out
          << "\" --set time.end=0.1 --set output.snapshot_interval=200";
  const pid_t child = pd::test_support::start_process({"/bin/sh", "-c", command.str()}, out + ".log");
  REQUIRE(child >= 0);
  for (int wait = 0; wait < 6000 && !fs::exists(folder + "/step_00000000.vtp"); ++wait) ::usleep(10000);
  const bool started = fs::exists(folder + "/step_00000000.vtp");
  std::error_code ignored;
  fs::remove_all(folder, ignored);
  for (int wait = 0; wait < 6000 && !fs::exists(folder); ++wait) ::usleep(10000);
  const bool made_again = fs::exists(folder);
  const int status = pd::test_support::interrupt_and_wait(child, SIGINT);
  REQUIRE(started);
  REQUIRE(made_again);
  const std::string log = file_text(out + ".log");
  INFO(log);
  CHECK(status == 1);
  CHECK(occurrences(log, "warning: " + folder + ": removed during the run, made again for the snapshot of step ") ==
        1);
  CHECK(occurrences(log, "; snapshots.pvd lists the snapshots of the steps before, whose files went with it "
                         "(ParaView and pd-post will not find them); run again to have the whole series\n") == 1);
  CHECK(occurrences(log, "pd-solve: error: interrupted by SIGTERM at step ") == 1);
  check_said_once_by_the_root(log);
}

// A scene error that the set-up of the whole plate finds (OSB, dual
// horizons: every process makes it, docs/solver.md, "Set-up"), a pre-crack
// that cuts no bond or a load's point outside the plate: every process
// finds it, the root says so once (before 7 December 2026 each process said
// it with its rank, and MPI_Abort's banner followed).
TEST_CASE("a pre-crack or a load the whole plate's set-up refuses is refused once on 2 processes", "[mpi]") {
  const Case c = make_small_case("whole_plate_refusals");
  const std::string scene_text = file_text(c.scene);
  const std::vector<std::pair<std::string, std::string>> models{
      {"osb", "[model]\ntype = \"osb\"\n"},
      {"dual", "[model]\ndual_horizon = true\n[effects]\nsurface_correction = false\n"}};
  const std::vector<std::pair<std::string, std::string>> refusals{
      {"[[precracks]]\nfrom = [0.06, 0.03]\nto = [0.07, 0.03]\n",
       "precracks[0] from [0.06, 0.03] to [0.07, 0.03] m cuts no bond: it lies outside the plate"},
      {"[[loads]]\nnearest = [1.0, 2.0]\ntype = \"fixed\"\n",
       "key 'loads[2].nearest' = [1, 2]: the nearest particle, at (0.0495, 0.0245) m, is 2.19227 m away"}};
  for (const auto& [model, model_table] : models)
    for (const auto& [table, said] : refusals) {
      if (model == "dual" && table != refusals[0].first) continue;  // (the loads are resolved as for OSB)
      INFO(model << ": " << said);
      std::ofstream(c.scene) << scene_text << model_table << table;
      const std::string out = c.folder + "/" + model + std::to_string(table.size());
      CHECK(run_within_a_minute(c, 2, "", out, "--threads 1") == 1);
      const std::string log = file_text(out + ".log");
      INFO(log);
      CHECK(occurrences(log, said) == 1);
      CHECK(occurrences(log, "pd-solve: error: " + c.scene + ":") == 1);
      check_said_once_by_the_root(log);
    }
}

// The band set-up (PMB, one horizon) resolves the loads and the stop region
// while the particle file streams by, and cuts the slabs: an error there is
// the scene's or the process count's, said as on one process, without the
// note that sends the user to the particle file (before 7 December 2026 it
// ended "(the particle file of S.toml, key 'particles'; pd-mesh writes it:
// see the scene's first lines)"); a damaged file still gets that note.
TEST_CASE("a load, a stop region or a process count the band set-up refuses is named as on one process",
          "[mpi][band]") {
  const Case c = make_small_case("band_refusals");
  const std::string scene_text = file_text(c.scene);
  const std::string note = "(the particle file of";
  const std::vector<std::pair<std::string, std::string>> refusals{
      {"[[loads]]\nset = \"topp\"\ntype = \"fixed\"\n",
       ": key 'loads[2].set' = \"topp\": no such boundary set in the particle file (known: left, right, bottom, top, "
       "or \"all\")\n"},
      {"[stop]\nbox = [1.0, 1.0, 2.0, 2.0]\ndamage = 0.35\n",
       ": key 'stop': box [1, 1, 2, 2] contains no particle (the plate spans x in [0, 0.05], y in [0, 0.025] m; box "
       "coordinates are in m, [xmin, ymin, xmax, ymax])\n"}};
  for (const auto& [table, said] : refusals) {
    INFO(said);
    std::ofstream(c.scene) << scene_text << table;
    const std::string two = c.folder + "/two" + std::to_string(table.size());
    CHECK(run_within_a_minute(c, 2, "", two, "--threads 1") == 1);
    const std::string log = file_text(two + ".log");
    INFO(log);
    CHECK(occurrences(log, "pd-solve: error: " + c.scene) == 1);
    CHECK(occurrences(log, said) == 1);
    CHECK(occurrences(log, note) == 0);
    CHECK(occurrences(log, "pd-solve: error:") == 1);
  }
  // More slabs than a plate of 4 columns of particles (4 mm x 2 mm at 1 mm):
  // the process count is at fault.
  std::ofstream(c.scene) << scene_text;
  const std::string tiny = c.folder + "/tiny";
  std::ofstream(tiny + ".geo") << "Point(1) = {0, 0, 0};\nPoint(2) = {4, 0, 0};\nPoint(3) = {4, 2, 0};\n"
                                  "Point(4) = {0, 2, 0};\nLine(1) = {1, 2};\nLine(2) = {2, 3};\nLine(3) = {3, 4};\n"
                                  "Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n";
  REQUIRE(run_shell(std::string("\"") + PD_MESH_EXECUTABLE + "\" \"" + tiny + ".geo\" --spacing 1mm --horizon 1.5mm -o \"" +
                    tiny + ".pdp\" > \"" + tiny + ".mesh.log\" 2>&1") == 0);
  const std::string many = c.folder + "/many";
  CHECK(run_within_a_minute(c, 5, "", many, "--threads 1 --set particles=\\\"" + tiny + ".pdp\\\"") == 1);
  const std::string many_log = file_text(many + ".log");
  INFO(many_log);
  CHECK(occurrences(many_log, "pd-solve: error: " + tiny + ".pdp: cannot cut 8 particles into 5 slabs of balanced "
                              "bonds along x; run on fewer processes (mpirun -np)\n") == 1);
  CHECK(occurrences(many_log, note) == 0);
  // A damaged particle file: the note names the scene's key that points there.
  const std::string damaged = c.folder + "/damaged.pdp";
  {
    const std::string bytes = file_text(c.particles);
    std::ofstream(damaged, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const std::string cut = c.folder + "/cut";
  CHECK(run_within_a_minute(c, 2, "", cut, "--threads 1 --set particles=\\\"" + damaged + "\\\"") == 1);
  const std::string cut_log = file_text(cut + ".log");
  INFO(cut_log);
  CHECK(occurrences(cut_log, "pd-solve: error: " + damaged + ": truncated") == 1);
  CHECK(occurrences(cut_log, note + " " + c.scene + ", --set, key 'particles'") == 1);
}

TEST_CASE("each process's lattice sweep holds a window of the plate's grid around its slab", "[mpi][band]") {
  // C3-A at 0.1 mm: 500 columns of squares. On 3 processes a slab is a third
  // of them; its window adds the ghosts and empty margins (2 horizons and a
  // SIMD step on each side) and starts at a whole column tile (128 cells), so
  // that tiles and row blocks fall on the same cells as in the whole grid
  // (LatticeKernel's constructor; the runs' results equal one process's, as
  // the tests above check); rows are padded to an odd number of 16-cell
  // cache lines (up to 31 cells). Bound: (500 / 3 + 2 (2 x 4 + 8) + 2 x 4 +
  // 127 + 31) / 524 = 0.70 of one process's rows, which hold the whole padded
  // plate (at least 500 + 2 x 4 + 16 cells).
  const Case c = make_case("grid_window", "pmb", "--spacing 0.1mm --horizon 0.4mm");
  const std::string one = c.folder + "/run1", three = c.folder + "/run3";
  REQUIRE(run_on_processes(c, 1, one, "--set time.end=2e-8") == 0);
  REQUIRE(run_on_processes(c, 3, three, "--set time.end=2e-8") == 0);
  const double whole = summary_field(one, "lattice_grid_cells_max"), window = summary_field(three, "lattice_grid_cells_max");
  INFO("grid cells: " << window << " of " << whole);
  CHECK(whole > 500 * 250);
  CHECK(window < 0.70 * whole);
}
