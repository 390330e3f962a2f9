#include "calculix.hpp"

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "atomic_file.hpp"
#include "error.hpp"

namespace pd::validation {
namespace {

void write_node_set(std::ostream& out, const std::string& name, const std::vector<std::size_t>& ids) {
  out << "*NSET, NSET=" << name << "\n";
  for (std::size_t k = 0; k < ids.size(); ++k) out << ids[k] << (k % 10 == 9 || k + 1 == ids.size() ? ",\n" : ", ");
}

std::string tail_of(const std::string& path, std::size_t lines) {
  std::ifstream in(path);
  std::vector<std::string> all;
  for (std::string line; std::getline(in, line);) all.push_back(line);
  std::string out;
  for (std::size_t k = all.size() > lines ? all.size() - lines : 0; k < all.size(); ++k) out += "\n  " + all[k];
  return out;
}

// Nodal displacements of the .frd result file: the block after "-4  DISP",
// records " -1" + node (I10) + 3 values (E12.5), ended by " -3".
void read_frd_displacements(const std::string& path, const FemMesh& mesh, FemSolution& s) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the CalculiX result file");
  std::map<std::size_t, std::size_t> index;
  for (std::size_t k = 0; k < mesh.node_id.size(); ++k) index[mesh.node_id[k]] = k;
  s.ux.assign(mesh.x.size(), NAN);
  s.uy.assign(mesh.x.size(), NAN);
  bool in_block = false, found = false;
  std::size_t read = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(" -4  DISP", 0) == 0) {
      in_block = found = true;
      continue;
    }
    if (!in_block) continue;
    if (line.rfind(" -3", 0) == 0) break;
    if (line.rfind(" -1", 0) != 0 || line.size() < 37) continue;
    const std::size_t node = std::stoul(line.substr(3, 10));
    const auto it = index.find(node);
    if (it == index.end()) continue;  // nodes ccx added for the expanded 3D layer
    s.ux[it->second] = std::stod(line.substr(13, 12));
    s.uy[it->second] = std::stod(line.substr(25, 12));
    ++read;
  }
  if (!found) throw Error(path + ": no displacement block (-4  DISP) in the CalculiX result file");
  for (std::size_t k = 0; k < s.ux.size(); ++k)
    if (!std::isfinite(s.ux[k]))
      throw Error(path + ": no displacement for node " + std::to_string(mesh.node_id[k]) + " (" +
                  std::to_string(read) + " nodes read)");
}

// " total force (fx,fy,fz) for set NAME and time ..." followed by a line of
// three numbers; `component` 0 = x, 1 = y.
double read_total_force(const std::string& path, const std::string& set, int component) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the CalculiX .dat file");
  for (std::string line; std::getline(in, line);) {
    if (line.find("total force") == std::string::npos || line.find(set) == std::string::npos) continue;
    std::string values;
    while (std::getline(in, values) && values.find_first_not_of(" \t\r") == std::string::npos) {
    }
    std::istringstream v(values);
    double f[2] = {NAN, NAN};
    v >> f[0] >> f[1];
    if (std::isfinite(f[component])) return f[component];
  }
  throw Error(path + ": no total force for node set " + set);
}

}  // namespace

std::string ccx_status_text(int status) {
  if (WIFEXITED(status)) return "ccx exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "ccx was killed by signal " + std::to_string(WTERMSIG(status));
  return "ccx ended with wait status " + std::to_string(status);
}

bool calculix_available() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

FemSolution run_calculix(const FemMesh& mesh, const PlateGeometry& g, const FemLoadCase& load,
                         const std::string& job_name) {
  const std::filesystem::path folder = std::filesystem::path(mesh.inp_mesh_file).parent_path();
  const std::string job = (folder / job_name).string();
  if (!calculix_available())
    throw Error(job + ".inp: the CalculiX solver 'ccx' is not on the PATH (Debian package calculix-ccx; "
                "scripts/install-deps.sh installs it)");
  // Strips of clamped nodes (left and right, or bottom and top with
  // along_y); the node nearest to the middle of the left (bottom) edge is held
  // across the pull against the rigid translation.
  const double tol = 1e-9;
  std::vector<std::size_t> left, right, pin;
  std::size_t pin_node = 0;
  double pin_distance = INFINITY;
  const int pull = load.along_y ? 1 : 0;  // the component the strips move
  const double low = load.along_y ? g.ymin : g.xmin, high = load.along_y ? g.ymax : g.xmax;
  const double pin_x = load.along_y ? 0.5 * (g.xmin + g.xmax) : g.xmin;
  const double pin_y = load.along_y ? g.ymin : 0.5 * (g.ymin + g.ymax);
  for (std::size_t k = 0; k < mesh.x.size(); ++k) {
    const double along = load.along_y ? mesh.y[k] : mesh.x[k];
    if (along <= low + load.clamp_width + tol) left.push_back(mesh.node_id[k]);
    if (along >= high - load.clamp_width - tol) right.push_back(mesh.node_id[k]);
    const double d = std::hypot(mesh.x[k] - pin_x, mesh.y[k] - pin_y);
    if (d < pin_distance) pin_distance = d, pin_node = mesh.node_id[k];
  }
  pin.push_back(pin_node);
  if (left.empty() || right.empty()) throw Error(job + ".inp: no nodes in the clamped strips");
  const int dof = pull + 1, pin_dof = 2 - pull;  // CalculiX degrees of freedom: 1 = x, 2 = y
  const double first_value = load.along_y ? load.bottom_uy : load.left_ux;
  const double second_value = load.along_y ? load.top_uy : load.right_ux;

  write_atomically(job + ".inp", [&](std::ofstream& out) {
    out << std::setprecision(12);  // ccx reads at most 20 characters per number
    out << "** Plane-stress linear-elastic reference (written by the validation library)\n"
        << "*INCLUDE, INPUT=" << std::filesystem::path(mesh.inp_mesh_file).filename().string() << "\n";
    write_node_set(out, "NLEFT", left);
    write_node_set(out, "NRIGHT", right);
    write_node_set(out, "NPIN", pin);
    out << "*MATERIAL, NAME=PLATE_MATERIAL\n*ELASTIC\n"
        << load.youngs_modulus << ", " << load.poisson_ratio << "\n"
        << "*SOLID SECTION, ELSET=" << mesh.element_set << ", MATERIAL=PLATE_MATERIAL\n"
        << load.section_thickness << "\n"
        << "*STEP\n*STATIC\n*BOUNDARY\n"
        << "NLEFT, " << dof << ", " << dof << ", " << first_value << "\n"
        << "NRIGHT, " << dof << ", " << dof << ", " << second_value << "\n"
        << "NPIN, " << pin_dof << ", " << pin_dof << ", 0\n"
        << "*NODE FILE\nU\n"
        << "*NODE PRINT, NSET=NLEFT, TOTALS=ONLY\nRF\n"
        << "*NODE PRINT, NSET=NRIGHT, TOTALS=ONLY\nRF\n"
        << "*END STEP\n";
  });
  const auto start = std::chrono::steady_clock::now();
  // (exec: the status is ccx's own, a signal that ends it too, not the shell's 128 + N.)
  const std::string command = "cd '" + folder.string() + "' && OMP_NUM_THREADS=1 exec ccx -i " + job_name + " > " +
                              job_name + ".log 2>&1";
  const int status = std::system(command.c_str());
  FemSolution s;
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0)
    throw Error(job + ".inp: " + ccx_status_text(status) + "; end of " + job + ".log:" +
                tail_of(job + ".log", 12));
  read_frd_displacements(job + ".frd", mesh, s);
  s.left_reaction_x = read_total_force(job + ".dat", "NLEFT", pull) / load.section_thickness;
  s.right_reaction_x = read_total_force(job + ".dat", "NRIGHT", pull) / load.section_thickness;
  return s;
}

}  // namespace pd::validation
