// Checkpoint and --restart: continuing from a checkpoint gives bit-identical
// results to an uninterrupted run; the roll-back after a blow-up returns to
// the saved state as a full restore does.
#include <catch2/catch.hpp>
#include <csignal>
#include <cstdio>
#include <omp.h>

#include <algorithm>
#include <filesystem>

#include <fstream>
#include <iterator>
#include <sstream>

#include "atomic_file.hpp"
#include "checkpoint.hpp"
#include "interrupt.hpp"
#include "error.hpp"
#include "results_format.hpp"
#include "lattice.hpp"
#include "run.hpp"
#include "simulation.hpp"
#include "test_support.hpp"
#include "../test_commands.hpp"

using namespace pd::solver;

namespace {

using pd::test_support::existing_file_text;

// A plate pulled apart at top and bottom with a pre-crack: bonds break during the run.
Scene cracking_scene(const std::string& plate, double dx) {
  auto s = test::basic_scene();
  s.particle_file = plate;
  s.effects.damage = true;
  s.effects.surface_correction = true;
  s.time.automatic = false;
  s.time.step = 2e-8;
  s.output.energy_interval = 10;
  s.output.snapshot_interval = 40;
  s.output.checkpoint_interval = 50;
  LoadSpec top;
  top.name = "top";
  top.kind = LoadKind::velocity;
  top.region.set = "top";
  top.has_y = true;
  top.y = 20.0;
  LoadSpec bottom = top;
  bottom.name = "bottom";
  bottom.region.set = "bottom";
  bottom.y = -20.0;
  s.loads = {top, bottom};
  s.precracks = {{{0.0, 10 * dx}, {6 * dx, 10 * dx}}};
  s.restart_key_text = "cracking test scene";
  return s;
}

// A scene for the checkpoint keys' tests (parse_scene only: no particle file is read).
const char* const keyed_scene_text = R"(particles = "plate.pdp"
[material]
youngs_modulus = "3.24 GPa"
density = 1190
fracture_energy = 200
poisson_ratio = 0.35
[time]
step = 2e-8
end = 1e-5
[[loads]]
set = "hole 2 edge"
type = "velocity"
y = 0.3
[output]
energy_interval = 10
)";

// The checkpoint key of `text` with `overrides` (--set), on one process.
std::string key_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return checkpoint_key(parse_scene(text, "dir/scene.toml", overrides).restart_key_text, "0123", 1);
}

// keyed_scene_text with its first `from` replaced by `to`.
std::string keyed_scene_with(const std::string& from, const std::string& to) {
  std::string text = keyed_scene_text;
  REQUIRE(text.find(from) != std::string::npos);
  return text.replace(text.find(from), from.size(), to);
}

// Why the checkpoint `path` is refused for a run of `key`, or "restarts".
std::string refusal(const std::string& path, const std::string& key) {
  try {
    read_checkpoint(path, key);
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "restarts";
}
}  // namespace

TEST_CASE("restart from a checkpoint equals the uninterrupted run bit for bit", "[restart]") {
  // Both model types: OSB's lattice sweeps keep per-cell dilatation sums
  // between their two passes, which must start from the saved state alone.
  // And dual-horizon OSB (theory.md Sec. 6.8) on a plate whose right half is
  // refined 2x: its bond states hold own and dual entries.
  const int variant = GENERATE(0, 1, 2);  // PMB, OSB, dual-horizon OSB
  const auto model = variant == 0 ? ModelType::pmb : ModelType::osb;
  const bool dual_horizon = variant == 2;
  const auto folder = test::fresh_folder(dual_horizon ? "restart-osb-dual-horizon"
                                                      : model == ModelType::osb ? "restart-osb" : "restart");
  const double dx = 1e-4;
  std::string plate;
  if (dual_horizon) {
    plate = folder + "/plate.pdp";
    pd::write_particle_file(plate, test::half_refined_plate(30 * dx, 20 * dx, dx, 3, 2));
  } else {
    plate = test::write_plate(folder, "plate.pdp", 30 * dx, 20 * dx, dx, 3 * dx);
  }
  auto scene = cracking_scene(plate, dx);
  scene.model = model;
  if (model == ModelType::osb) scene.material.poisson_ratio = 0.35;
  if (dual_horizon) {
    scene.dual_horizon = true;
    scene.effects.surface_correction = false;  // not available with variable horizons
  }
  std::ostringstream log;
  RunOptions options = test::quiet_options(log);

  scene.time.end = 160 * scene.time.step;
  options.output_dir = folder + "/whole";
  const auto whole = run_scene(scene, options);
  CHECK(whole.steps == 160);
  // Dual-horizon OSB sends the coarse half's inner squares through the
  // lattice sweep and keeps dual-horizon rows for the others (theory.md
  // Sec. 6.8): the checkpoint holds the sweep's bits and the rows' entries.
  if (dual_horizon) {
    CHECK(log.str().find("kernel:    lattice sweep for ") != std::string::npos);
    CHECK(log.str().find("dual-horizon rows for ") != std::string::npos);
  }

  // Interrupted after 100 steps (the last checkpoint), then continued.
  scene.time.end = 100 * scene.time.step;
  options.output_dir = folder + "/split";
  CHECK(run_scene(scene, options).steps == 100);
  // As a run killed after its checkpoint leaves them: snapshots of later
  // steps (one the continued run writes again, two it never reaches or
  // passes without one), beside a file of the user's.
  for (const char* name : {"step_00000120.vtp", "step_00000150.vtp", "step_00000200.vtp", "mine.vtp"})
    std::ofstream(folder + "/split/snapshots/" + name) << "a killed run's";
  // pd-post's pictures of the first part, and a table of the user's beside them.
  std::filesystem::create_directories(folder + "/split/post");
  for (const char* name : {"damage_final.png", "crack_tips.csv", "measured.csv"})
    std::ofstream(folder + "/split/post/" + name) << "of the first part";
  std::ofstream(folder + "/split/post/summary.json") << "{\n  \"tool\": \"pd-post 0.1.0\"\n}\n";  // pd-post's mark
  scene.time.end = 160 * scene.time.step;
  options.restart = true;
  CHECK(run_scene(scene, options).steps == 160);
  CHECK_FALSE(std::filesystem::exists(folder + "/split/snapshots/step_00000150.vtp"));
  CHECK_FALSE(std::filesystem::exists(folder + "/split/snapshots/step_00000200.vtp"));
  CHECK(existing_file_text(folder + "/split/snapshots/step_00000120.vtp") ==
        existing_file_text(folder + "/whole/snapshots/step_00000120.vtp"));
  CHECK(std::filesystem::exists(folder + "/split/snapshots/mine.vtp"));
  CHECK_FALSE(std::filesystem::exists(folder + "/split/post/damage_final.png"));
  CHECK_FALSE(std::filesystem::exists(folder + "/split/post/crack_tips.csv"));
  CHECK_FALSE(std::filesystem::exists(folder + "/split/post/summary.json"));
  CHECK(std::filesystem::exists(folder + "/split/post/measured.csv"));

  // Ended after 135 steps, between two checkpoints and two energy rows: the run's last step is
  // checkpointed too (without the end's extra energy row), and the restart
  // goes on from step 135.
  scene.time.end = 135 * scene.time.step;
  options.restart = false;
  options.output_dir = folder + "/ended";
  CHECK(run_scene(scene, options).steps == 135);
  // Its snapshots end with the last step's, off the interval of 40.
  CHECK(std::filesystem::exists(folder + "/ended/snapshots/step_00000135.vtp"));
  CHECK(existing_file_text(folder + "/ended/" + pd::results::snapshot_collection).find("step_00000135.vtp") !=
        std::string::npos);
  // Stopped after the checkpoint of its last step, before its end files (no
  // summary.json): a restart to the same end takes no step and writes them,
  // as the run would have; with summary.json it is refused (nothing to do).
  {
    const std::string energy_ended = existing_file_text(folder + "/ended/" + pd::results::energy_file);
    const std::string arrival_ended = existing_file_text(folder + "/ended/" + pd::results::arrival_file);
    options.restart = true;
    CHECK_THROWS_WITH(run_scene(scene, options), Catch::Contains("is not after the time of"));
    std::filesystem::remove(folder + "/ended/" + pd::results::summary_file);
    std::filesystem::remove(folder + "/ended/" + pd::results::energy_file);
    CHECK(run_scene(scene, options).steps == 135);
    CHECK(existing_file_text(folder + "/ended/" + pd::results::energy_file) == energy_ended);
    CHECK(existing_file_text(folder + "/ended/" + pd::results::arrival_file) == arrival_ended);
    CHECK(std::filesystem::exists(folder + "/ended/" + pd::results::summary_file));
    options.restart = false;
  }
  scene.time.end = 160 * scene.time.step;
  options.restart = true;
  CHECK(run_scene(scene, options).steps == 160);
  CHECK(log.str().find("steps:     135 -> 160") != std::string::npos);
  // The continued run passes step 135 without a snapshot, as the uninterrupted one.
  CHECK_FALSE(std::filesystem::exists(folder + "/ended/snapshots/step_00000135.vtp"));

  const auto arrival_whole = existing_file_text(folder + "/whole/" + pd::results::arrival_file);
  for (const char* restarted : {"/split/", "/ended/"}) {
    INFO(restarted);
    CHECK(arrival_whole == existing_file_text(folder + restarted + pd::results::arrival_file));
    CHECK(existing_file_text(folder + "/whole/" + pd::results::energy_file) ==
          existing_file_text(folder + restarted + pd::results::energy_file));
    CHECK(existing_file_text(folder + "/whole/snapshots/step_00000160.vtp") ==
          existing_file_text(folder + restarted + "snapshots/step_00000160.vtp"));
    CHECK(existing_file_text(folder + "/whole/" + pd::results::snapshot_collection) ==
          existing_file_text(folder + restarted + pd::results::snapshot_collection));
  }
  // The run really broke bonds (so the bond state went through the checkpoint).
  CHECK(existing_file_text(folder + "/whole/" + pd::results::energy_file).find(",0,") != std::string::npos);
  const auto checkpoint = read_checkpoint(folder + "/whole/" + checkpoint_file, "cracking test scene\nparticles " +
                                                                                    pd::file_hash_hex(plate));
  std::size_t damaged = 0;
  for (double d : checkpoint.state.damage) damaged += d > 0;
  CHECK(checkpoint.state.step == 160);  // the end's (the last interval's was step 150)
  CHECK(damaged > 0);
}

TEST_CASE("a corrupt or foreign checkpoint is refused", "[restart]") {
  const auto folder = test::fresh_folder("restart-refused");
  const double dx = 1e-4;
  const auto plate = test::write_plate(folder, "plate.pdp", 20 * dx, 20 * dx, dx, 3 * dx);
  auto scene = cracking_scene(plate, dx);
  scene.time.end = 50 * scene.time.step;
  std::ostringstream log;
  RunOptions options = test::quiet_options(log);
  options.output_dir = folder + "/out";
  run_scene(scene, options);
  const std::string path = folder + "/out/" + checkpoint_file;
  const std::string key = checkpoint_key("cracking test scene", pd::file_hash_hex(plate), 1);
  CHECK_NOTHROW(read_checkpoint(path, key));
  CHECK_THROWS_WITH(read_checkpoint(path, "another scene"), Catch::Contains("different scene"));
  // The message names what differs: the particle file's content (its hash), in words.
  CHECK_THROWS_WITH(read_checkpoint(path, checkpoint_key("cracking test scene", "0123", 1)),
                    Catch::Contains("checkpoint belongs to another particle file (its content changed since the "
                                    "checkpoint was written: " +
                                    pd::file_hash_hex(plate) + " then, 0123 now)"));
  // The process count is not part of the match: its line in the key says
  // how the bond states are laid out (since 8 December 2026; before, a run
  // on several processes refused it: 'checkpoint was written by a run on one
  // process, and this run is on several: restart it on one process (without
  // mpirun)', and the other way round).
  {
    const std::string several = checkpoint_key("cracking test scene", pd::file_hash_hex(plate), 2);
    const Checkpoint one_process = read_checkpoint(path, several);
    CHECK_FALSE(one_process.state.bond_states_by_family);
    CHECK_FALSE(check_checkpoint(path, several));
    const std::string by_family = folder + "/by_family.bin";
    write_checkpoint(by_family, several, one_process);
    CHECK(read_checkpoint(by_family, key).state.bond_states_by_family);
    CHECK(check_checkpoint(by_family, key));
    // A one-process restart reads it whole, not into its own arrays.
    Simulation::State state = one_process.state;
    CHECK_THROWS_WITH(read_checkpoint_in_place(by_family, key, state), Catch::Contains("read whole"));
  }
  // A checkpoint of the other mode names both (before 6 December 2026:
  // "checkpoint of the other mode (dynamic / quasi-static)", neither said).
  CHECK_THROWS_WITH(read_quasi_static_checkpoint(path, key),
                    Catch::Contains(path + ": a dynamic run's checkpoint (PDCHK003), and this run is quasi-static: "
                                           "--restart continues the run that wrote it, with its scene"));
  {
    const std::string quasi_static = folder + "/quasi_static.bin";
    write_checkpoint(quasi_static, key, QuasiStaticCheckpoint{});
    CHECK_THROWS_WITH(read_checkpoint(quasi_static, key),
                      Catch::Contains(quasi_static + ": a quasi-static run's checkpoint (PDQSC002), and this run is "
                                                     "dynamic: --restart continues the run that wrote it"));
  }
  {
    // A checkpoint of the format before the energy checks' state
    // (PDCHK002, before the third sitting of 6 December 2026): refused by
    // its format, which a restart could not continue as the run that wrote it.
    std::string older = pd::test_support::file_text(path);
    older.replace(0, 8, "PDCHK002");
    const std::string older_path = folder + "/older.bin";
    std::ofstream(older_path, std::ios::binary) << older;
    CHECK_THROWS_WITH(read_checkpoint(older_path, key),
                      Catch::Contains(older_path + ": checkpoint format PDCHK002 of another pd-solve version (this "
                                                   "one reads PDCHK003); run again without --restart"));
  }
  {
    // Cut within the header: truncated, not another kind of file.
    const std::string whole = pd::test_support::file_text(path);
    const std::string cut = folder + "/cut.bin";
    std::ofstream(cut, std::ios::binary) << whole.substr(0, 20);
    CHECK_THROWS_WITH(read_checkpoint(cut, key), Catch::Contains("checkpoint is truncated (20 bytes)"));
    // Within the key: the size the header's key length needs (before, "checkpoint is truncated" alone).
    std::ofstream(cut, std::ios::binary) << whole.substr(0, 30);
    CHECK_THROWS_WITH(read_checkpoint(cut, key),
                      Catch::Contains(cut + ": checkpoint is truncated: 30 bytes, and its header's key of " +
                                      std::to_string(key.size()) + " bytes needs at least " +
                                      std::to_string(key.size() + 24)));
  }
  {
    // Cut within its payload (a copy interrupted, a disk that filled during
    // one): truncated, with the size it has and the size its arrays' counts
    // need (before 6 December 2026: "checkpoint checksum mismatch (file
    // corrupted)"). One byte short: the last energy row ends past the end,
    // so the counts need the whole file's length, checksum included.
    const std::string whole = pd::test_support::file_text(path);
    const std::string cut = folder + "/cut_payload.bin";
    std::ofstream(cut, std::ios::binary) << whole.substr(0, whole.size() - 1);
    CHECK_THROWS_WITH(read_checkpoint(cut, key),
                      Catch::Contains(cut + ": checkpoint is truncated: " + std::to_string(whole.size() - 1) +
                                      " bytes, where the counts of its arrays need at least " +
                                      std::to_string(whole.size()) + " (it ends within 'energy rows'") &&
                          !Catch::Contains("checksum"));
    // The early check of a restart on one process says the same.
    CHECK_THROWS_WITH(check_checkpoint(cut, key), Catch::Contains("checkpoint is truncated: "));
    // Cut in the middle, within an array of the state: that array's end is
    // the least the file needs.
    std::ofstream(cut, std::ios::binary) << whole.substr(0, whole.size() / 2);
    std::string message;
    try {
      read_checkpoint(cut, key);
    } catch (const pd::Error& e) {
      message = e.what();
    }
    INFO(message);
    const std::string needed_text = "the counts of its arrays need at least ";
    REQUIRE(message.find(needed_text) != std::string::npos);
    CHECK_THAT(message, Catch::Contains("checkpoint is truncated: " + std::to_string(whole.size() / 2) + " bytes"));
    const double needed = std::stod(message.substr(message.find(needed_text) + needed_text.size()));
    CHECK(needed > static_cast<double>(whole.size() / 2));
    CHECK(needed <= static_cast<double>(whole.size()));
    // A quasi-static checkpoint the same.
    const std::string quasi_static = folder + "/quasi_static_cut.bin";
    QuasiStaticCheckpoint steps;
    steps.state.load_factors_done = {0.5, 1.0};
    steps.state.u.assign(40, 1e-6);
    steps.load_step_rows = {"1,0.5", "2,1"};
    write_checkpoint(quasi_static, key, steps);
    const std::string quasi_static_whole = pd::test_support::file_text(quasi_static);
    std::ofstream(quasi_static, std::ios::binary) << quasi_static_whole.substr(0, quasi_static_whole.size() - 3);
    CHECK_THROWS_WITH(read_quasi_static_checkpoint(quasi_static, key),
                      Catch::Contains("checkpoint is truncated: " + std::to_string(quasi_static_whole.size() - 3) +
                                      " bytes, where the counts of its arrays need at least " +
                                      std::to_string(quasi_static_whole.size())));
  }
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-100, std::ios::end);
    f.put('\x7f');
  }
  // A whole-length file with a changed value: its own message.
  CHECK_THROWS_WITH(read_checkpoint(path, key), Catch::Contains("checkpoint checksum mismatch (file corrupted)") &&
                                                    !Catch::Contains("truncated"));
}

TEST_CASE("a restart may change how often checkpoints are written, and no other output key", "[restart]") {
  const auto folder = test::fresh_folder("restart-output-keys");
  const std::string path = folder + "/checkpoint.bin";
  write_checkpoint(path, key_of(keyed_scene_text), Checkpoint{});
  // How often checkpoints are written changes no result (test_executable.cpp:
  // the restarted run equals the uninterrupted one bit for bit); before 6
  // December 2026 it was part of the key.
  CHECK(refusal(path, key_of(keyed_scene_text, {"output.checkpoint_interval=30"})) == "restarts");
  CHECK(refusal(path, key_of(keyed_scene_text, {"output.checkpoint_interval=0"})) == "restarts");
  // The other output keys may not change, and the refusal says why.
  CHECK_THAT(refusal(path, key_of(keyed_scene_text, {"output.energy_interval=20"})),
             Catch::Contains("first difference: 'output.energy_interval = 10' in the checkpoint, "
                             "'output.energy_interval = 20' now; the energy interval cannot change on a restart") &&
                 Catch::Contains("energy.csv would change its spacing midway"));
  CHECK_THAT(refusal(path, key_of(keyed_scene_text, {"output.snapshot_interval=20"})),
             Catch::Contains("first difference: 'output.snapshot_interval = 20' now; the checkpoint's run left it out "
                             "(or had its default); the snapshot interval cannot change on a restart"));
  CHECK_THAT(refusal(path, key_of(keyed_scene_text, {"output.damage_thresholds=[0.5]"})),
             Catch::Contains("the damage thresholds cannot change on a restart: the checkpoint holds the arrival "
                             "times of its thresholds"));
}

TEST_CASE("a checkpoint's key tells scenes apart by what they mean, not how they are written", "[restart]") {
  const auto folder = test::fresh_folder("restart-key");
  const std::string path = folder + "/checkpoint.bin";
  write_checkpoint(path, key_of(keyed_scene_text), Checkpoint{});
  const auto restart_with = [&](const std::string& text, const std::vector<std::string>& overrides = {}) {
    return refusal(path, key_of(text, overrides));
  };

  // The same scene: a whole number as a decimal, hexadecimal or --set; a
  // value with another unit; keys in another order, comments, spaces.
  CHECK(restart_with(keyed_scene_with("density = 1190", "density = 1190.0")) == "restarts");
  CHECK(restart_with(keyed_scene_with("density = 1190", "density = \"1.19 g/cm^3\"")) == "restarts");
  CHECK(restart_with(keyed_scene_text, {"material.density=1190.0"}) == "restarts");
  CHECK(restart_with(keyed_scene_with("\"3.24 GPa\"", "\"3240 MPa\"")) == "restarts");
  CHECK(restart_with(keyed_scene_with("\"3.24 GPa\"", "3.24e9")) == "restarts");
  CHECK(restart_with(keyed_scene_with("\"3.24 GPa\"", "3240000000")) == "restarts");
  // toml++ keeps a hexadecimal whole number as written (before 6 December
  // 2026 refused as another scene: 'output.energy_interval = 0xA').
  CHECK(restart_with(keyed_scene_with("energy_interval = 10", "energy_interval = 0xA")) == "restarts");
  CHECK(restart_with(keyed_scene_with("energy_interval = 10", "energy_interval = 1_0")) == "restarts");
  CHECK(restart_with(keyed_scene_with("poisson_ratio = 0.35\n", "# nu\n  poisson_ratio   =   0.350 # as measured\n")) ==
        "restarts");
  CHECK(restart_with(keyed_scene_with("[time]\nstep = 2e-8\nend = 1e-5\n", "") + "[time]\nend = 1e-5\nstep = 20e-9\n") ==
        "restarts");

  // Another scene, named by its key and both values. A whole number inside
  // a string is text (before 6 December 2026 'hole 2 edge' and 'hole 2.0
  // edge', the sets of particles two loads act on, restarted).
  CHECK_THAT(restart_with(keyed_scene_with("hole 2 edge", "hole 2.0 edge")),
             Catch::Contains("first difference: 'loads[0].set = 'hole 2 edge'' in the checkpoint, "
                             "'loads[0].set = 'hole 2.0 edge'' now"));
  // The key that differs, not one spelt otherwise before it (before, the
  // message named material.density, '1190' then and '1190.0' now).
  CHECK_THAT(restart_with(keyed_scene_with("density = 1190", "density = 1190.0"), {"material.poisson_ratio=0.3"}),
             Catch::Contains("first difference: 'material.poisson_ratio = 0.35' in the checkpoint, "
                             "'material.poisson_ratio = 0.3' now"));
  // A whole number is quoted with its digits (before the second sitting of
  // 6 December 2026, 2e+06).
  CHECK_THAT(restart_with(keyed_scene_with("energy_interval = 10", "energy_interval = 2000000")),
             Catch::Contains("'output.energy_interval = 10' in the checkpoint, 'output.energy_interval = 2000000' now"));
  // Doubles that differ in their last bit are another scene (the run would
  // not be the same bit for bit): both are quoted with the digits that tell them apart.
  CHECK_THAT(restart_with(keyed_scene_text, {"material.poisson_ratio=0.35000000000000003"}),
             Catch::Contains("'material.poisson_ratio = 0.35' in the checkpoint, "
                             "'material.poisson_ratio = 0.35000000000000003' now"));
  // Dual-horizon PD changes the forces: a restart that turns it on or off is
  // refused, naming the key (before, the table: "'[model]' in the checkpoint").
  write_checkpoint(path, key_of(keyed_scene_text, {"model.dual_horizon=true"}), Checkpoint{});
  CHECK_THAT(restart_with(keyed_scene_text),
             Catch::Contains("first difference: 'model.dual_horizon = true' in the checkpoint; left out now"));
  CHECK_THAT(restart_with(keyed_scene_text, {"model.dual_horizon=false"}),
             Catch::Contains("first difference: 'model.dual_horizon = true' in the checkpoint; left out now"));
  CHECK(restart_with(keyed_scene_text, {"model.dual_horizon=true"}) == "restarts");

  // Numbers as toml++ writes them, compared by their doubles: a whole number
  // of 17 digits is written as digits, the same double as a decimal "1e+17".
  write_checkpoint(path, checkpoint_key("[loads]\nramp_time = 100000000000000000", "0123", 1), Checkpoint{});
  CHECK(refusal(path, checkpoint_key("[loads]\nramp_time = 1e+17", "0123", 1)) == "restarts");
  CHECK_THAT(refusal(path, checkpoint_key("[loads]\nramp_time = 1.0000000000000002e+17", "0123", 1)),
             Catch::Contains("'loads.ramp_time = 1e+17' in the checkpoint, 'loads.ramp_time = 1.0000000000000002e+17' now"));
}

// The run identifier (docs/formats.md, "Run identifier") follows the key a
// restart must match: one for every spelling the checkpoint restarts with,
// another for another material or particle file, whatever the end time.
TEST_CASE("a run's identifier is one for the scenes a checkpoint restarts, another for another scene",
          "[restart]") {
  const auto id_of = [](const std::string& text, const std::vector<std::string>& overrides = {},
                        const std::string& particle_hash = "0123") {
    return run_identifier(parse_scene(text, "dir/scene.toml", overrides).restart_key_text, particle_hash);
  };
  const std::string id = id_of(keyed_scene_text);
  CHECK(id.size() == 16);
  CHECK(id.find_first_not_of("0123456789abcdef") == std::string::npos);
  // The same run: spelt otherwise, extended, its checkpoints written at another interval.
  CHECK(id_of(keyed_scene_with("density = 1190", "density = 1190.0")) == id);
  CHECK(id_of(keyed_scene_with("\"3.24 GPa\"", "3240000000")) == id);
  CHECK(id_of(keyed_scene_with("energy_interval = 10", "energy_interval = 0xA")) == id);
  CHECK(id_of(keyed_scene_text, {"time.end=2e-5", "output.checkpoint_interval=50"}) == id);
  // Another run: another material value, load, output interval or particle file.
  CHECK(id_of(keyed_scene_with("density = 1190", "density = 1300")) != id);
  CHECK(id_of(keyed_scene_text, {"material.poisson_ratio=0.35000000000000003"}) != id);
  CHECK(id_of(keyed_scene_with("y = 0.3", "y = 0.4")) != id);
  CHECK(id_of(keyed_scene_text, {"output.snapshot_interval=20"}) != id);
  CHECK(id_of(keyed_scene_text, {}, "0124") != id);
}

TEST_CASE("a restart with a load renamed is refused, naming both names", "[restart]") {
  // A load's name heads its energy.csv columns (reaction_x_top_N, ...), whose
  // rows before the checkpoint were written under it. Before the third
  // sitting of 6 December 2026 the name was left out of the key (read as a
  // default it always equalled): a checkpoint of a load named 'top' restarted
  // a scene naming it 'pull', whose energy.csv header took the new name for
  // rows written under the old one.
  const auto folder = test::fresh_folder("restart-load-name");
  const std::string path = folder + "/checkpoint.bin";
  const std::string named = keyed_scene_with("type = \"velocity\"", "type = \"velocity\"\nname = \"top\"");
  write_checkpoint(path, key_of(named), Checkpoint{});
  CHECK(refusal(path, key_of(named)) == "restarts");
  CHECK_THAT(refusal(path, key_of(named, {"loads.top.name=pull"})),
             Catch::Contains("checkpoint belongs to a different scene or particle file") &&
                 Catch::Contains("first difference: 'loads[0].name = 'top'' in the checkpoint, "
                                 "'loads[0].name = 'pull'' now"));
  // Without its name the load goes by its set ('hole 2 edge'): another name.
  CHECK_THAT(refusal(path, key_of(keyed_scene_text)),
             Catch::Contains("first difference: 'loads[0].name = 'top'' in the checkpoint; left out now"));
  // A name equal to the one the load has without it (its set) is that
  // load's default: written or left out, one scene.
  write_checkpoint(path, key_of(keyed_scene_text), Checkpoint{});
  CHECK(refusal(path, key_of(keyed_scene_text, {"loads.0.name='hole 2 edge'"})) == "restarts");
  CHECK_THAT(refusal(path, key_of(keyed_scene_text, {"loads.0.name=edge"})),
             Catch::Contains("first difference: 'loads[0].name = 'edge'' now; the checkpoint's run left it out"));
}

TEST_CASE("results do not depend on the thread count", "[restart]") {
  // Each particle sums its own bonds in a fixed order, so 1 and 2 threads agree bit for bit.
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(30 * dx, 20 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = cracking_scene("in-memory", dx);
  const auto run_with = [&](int threads) {
    omp_set_num_threads(threads);
    Simulation sim(scene, p);
    for (int s = 0; s < 150; ++s) sim.step();
    return sim.save_state();
  };
  const int default_threads = omp_get_max_threads();
  const auto one = run_with(1), two = run_with(2);
  omp_set_num_threads(default_threads);
  CHECK(one.kinematics.ux == two.kinematics.ux);
  CHECK(one.kinematics.vy == two.kinematics.vy);
  CHECK(one.bond_states == two.bond_states);
  CHECK(std::count(one.bond_states.begin(), one.bond_states.end(), 0) > 0);
}

TEST_CASE("the stop condition ends the run early", "[restart]") {
  const auto folder = test::fresh_folder("stop");
  const double dx = 1e-4;
  const auto plate = test::write_plate(folder, "plate.pdp", 30 * dx, 20 * dx, dx, 3 * dx);
  auto scene = cracking_scene(plate, dx);
  scene.output.snapshot_interval = 0;
  scene.output.checkpoint_interval = 0;
  scene.time.end = 1000 * scene.time.step;
  scene.stop.enabled = true;
  scene.stop.region.has_box = true;
  scene.stop.region.box = {8 * dx, 9 * dx, 9 * dx, 11 * dx};  // just ahead of the pre-crack tip
  scene.stop.damage = 0.35;
  std::ostringstream log;
  RunOptions options = test::quiet_options(log);
  options.output_dir = folder + "/out";
  const auto report = run_scene(scene, options);
  INFO(log.str());
  CHECK(report.steps < 1000);
  CHECK_THAT(report.stop_reason, Catch::Contains("stop condition"));
  // It says where (before 5 December 2026 it did not: one particle beside a
  // loaded edge read as the crack arriving): a particle of the box, damaged
  // beyond the threshold.
  double x_mm = 0, y_mm = 0, damage = 0;
  const auto at = report.stop_reason.find("(at (");
  REQUIRE(at != std::string::npos);
  REQUIRE(std::sscanf(report.stop_reason.c_str() + at, "(at (%lf, %lf) mm, damage %lf)", &x_mm, &y_mm, &damage) == 3);
  CHECK(x_mm >= 0.8);
  CHECK(x_mm <= 0.9);
  CHECK(y_mm >= 0.9);
  CHECK(y_mm <= 1.1);
  CHECK(damage >= 0.35);
  std::ifstream summary(folder + "/out/" + pd::results::summary_file);
  const std::string text((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
  CHECK_THAT(text, Catch::Contains("\"stop_reason\": \"stop condition"));

  // With checkpoints the run's last step is checkpointed; a restart from it
  // would stop again at once and rewrite the results: refused, the summary kept.
  scene.output.checkpoint_interval = 5000;
  options.output_dir = folder + "/checkpointed";
  const long stopped_at = run_scene(scene, options).steps;
  CHECK(stopped_at < 1000);
  scene.time.end = 2000 * scene.time.step;
  options.restart = true;
  const std::string summary_before = pd::test_support::file_text(folder + "/checkpointed/" + pd::results::summary_file);
  CHECK_THROWS_WITH(run_scene(scene, options),
                    Catch::Contains("the run stopped on its stop condition at step " + std::to_string(stopped_at)) &&
                        Catch::Contains("a restart would stop again at once"));
  CHECK(pd::test_support::file_text(folder + "/checkpointed/" + pd::results::summary_file) == summary_before);
}

// A checkpoint of several processes holds the bond states family by family
// (docs/formats.md); one process restores them into its own kernels since 8
// December 2026, and a one-process run's own states are turned so for a
// restart on several (runs/checkpoint_layout.hpp). Reference: the run that
// never stopped, which the restored one must equal bit for bit, as a restart
// in the kernels' own layout does (the test above).
TEST_CASE("one process restores its bond states saved family by family as the run that never stopped", "[restart]") {
  // PMB and OSB on the lattice sweep, PMB on the neighbour lists alone, and
  // dual-horizon PMB and OSB on a plate whose right half is refined 2x (the
  // lattice split's general rows hold dual entries, which take their
  // owners' states).
  const int variant = GENERATE(0, 1, 2, 3, 4);
  const double dx = 1e-4;
  const bool dual_horizon = variant >= 3;
  const pd::ParticleSet p = dual_horizon ? test::half_refined_plate(30 * dx, 20 * dx, dx, 3, 2)
                                         : pd::make_rectangle_lattice(30 * dx, 20 * dx, dx, 3 * dx,
                                                                      pd::Quadrature::analytic);
  auto scene = cracking_scene("in-memory", dx);
  scene.model = variant == 1 || variant == 4 ? ModelType::osb : ModelType::pmb;
  scene.material.poisson_ratio = 0.35;
  if (dual_horizon) {
    scene.dual_horizon = true;
    scene.effects.surface_correction = false;  // not available with variable horizons
  }
  SetupOptions options;
  options.keep_families = true;
  options.lattice_kernel = variant != 2;
  Simulation sim(scene, p, options);
  for (int s = 0; s < 100; ++s) sim.step();
  Simulation::State saved = sim.save_state();
  CHECK_FALSE(saved.bond_states_by_family);
  sim.bond_states_by_family(saved.bond_states);
  saved.bond_states_by_family = true;
  CHECK(saved.bond_states.size() == sim.bond_count());  // one state per directed bond
  const auto broken_then = sim.broken_bond_count();
  REQUIRE(broken_then > 0);

  Simulation restored(scene, p, options);
  restored.restore_state(saved);
  CHECK(restored.broken_bond_count() == broken_then);
  for (int s = 0; s < 60; ++s) sim.step(), restored.step();
  CHECK(sim.broken_bond_count() > broken_then);  // bonds broke after the restore too
  CHECK(restored.broken_bond_count() == sim.broken_bond_count());
  CHECK(restored.kinematics().ux == sim.kinematics().ux);
  CHECK(restored.kinematics().vy == sim.kinematics().vy);
  CHECK(restored.damage() == sim.damage());
  CHECK(restored.arrival_times() == sim.arrival_times());
}

TEST_CASE("a roll-back returns to the saved state as a full restore does", "[restart]") {
  // Reference: restore_state, which puts back every saved array bit for bit
  // (the restart test above). The roll-back state keeps displacements,
  // velocities and bond states only; forces, damage and arrival times must
  // come out the same.
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(30 * dx, 20 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = cracking_scene("in-memory", dx);
  scene.output.damage_thresholds = {1e-3, 0.05};  // low: the steps in between must record arrivals
  Simulation sim(scene, p);
  for (int s = 0; s < 100; ++s) sim.step();
  const auto full = sim.save_state();
  Simulation::State light;
  sim.save_rollback_state(light);
  const auto broken_then = sim.broken_bond_count();
  for (int s = 0; s < 60; ++s) sim.step();
  // The steps in between broke bonds and recorded arrival times.
  REQUIRE(sim.broken_bond_count() > broken_then);
  REQUIRE(sim.arrival_times() != full.arrival);

  sim.roll_back(light);
  CHECK(sim.step_index() == full.step);
  CHECK(sim.time() == full.time);
  CHECK(sim.external_work() == full.external_work);
  CHECK(sim.broken_bond_count() == broken_then);
  CHECK(sim.kinematics().ux == full.kinematics.ux);
  CHECK(sim.kinematics().vy == full.kinematics.vy);
  CHECK(sim.kinematics().fx == full.kinematics.fx);
  CHECK(sim.kinematics().fy == full.kinematics.fy);
  CHECK(sim.damage() == full.damage);
  CHECK(sim.arrival_times() == full.arrival);
}

// The first Ctrl-C asks the run to stop after its step (docs/solver.md,
// "Interrupting a run"); a second one must end the process at once, for a
// run whose checkpoint is slow to write or that hangs. The handler gives the
// signal its default action back when it is called, and the caught signal
// stays readable; when the run's catching ends, the handlers before it are
// back.
TEST_CASE("after the first Ctrl-C a second one ends the process: its action is the default again", "[restart]") {
  const auto action = [](int signal) {
    struct sigaction current {};
    ::sigaction(signal, nullptr, &current);
    return current.sa_handler;
  };
  const auto before = std::signal(SIGINT, SIG_IGN);  // a handler of the caller's, to be put back
  {
    pd::solver::CatchInterrupts catching;
    CHECK(pd::solver::interrupt_signal() == 0);
    CHECK(action(SIGINT) != SIG_DFL);
    CHECK(action(SIGINT) != SIG_IGN);
    CHECK(action(SIGTERM) != SIG_DFL);
    std::raise(SIGINT);
    CHECK(pd::solver::interrupt_signal() == SIGINT);
    CHECK(action(SIGINT) == SIG_DFL);   // the next Ctrl-C ends the process
    CHECK(action(SIGTERM) != SIG_DFL);  // SIGTERM is still caught once
  }
  CHECK(action(SIGINT) == SIG_IGN);
  std::signal(SIGINT, before);
}
