#include "report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "atomic_file.hpp"
#include "pd/version.hpp"

namespace pd::post {
namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  if (v == 0) return "0";  // not "-0"
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') { out += "\\n"; continue; }
    out += c;
  }
  return out + "\"";
}

}  // namespace

void write_tip_table(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "time_s,branch,x_m,y_m\n";
    for (const auto& tip : r.tips)
      for (std::size_t k = 0; k < tip.time.size(); ++k)
        out << num(tip.time[k]) << ',' << tip.branch << ',' << num(tip.x[k]) << ',' << num(tip.y[k]) << '\n';
  });
}

void write_speed_table(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "time_s,branch,speed_m_per_s,speed_over_rayleigh,tip_x_m,across_pore,tip_jump\n";
    for (const auto& s : r.speeds)
      out << num(s.time) << ',' << s.branch << ',' << num(s.speed) << ',' << num(s.speed / r.rayleigh_speed)
          << ',' << num(s.tip_x) << ',' << (s.across_pore ? 1 : 0) << ',' << (s.tip_jump ? 1 : 0) << '\n';
  });
}

void write_branch_table(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "branch,parent,start_time_s,start_x_m,start_y_m,end_time_s,end_x_m,end_y_m,length_m\n";
    for (std::size_t b = 0; b < r.network.branches.size(); ++b) {
      const auto& br = r.network.branches[b];
      const auto& tip = r.tips[b];
      out << br.id << ',' << br.parent << ',' << num(br.start_time) << ',' << num(br.origin_x) << ','
          << num(br.origin_y) << ',' << num(br.end_time) << ',' << num(tip.x.back()) << ','
          << num(tip.y.back()) << ',' << num(tip_path_length(tip)) << '\n';
    }
  });
}

void write_pore_table(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "pore,x_m,y_m,radius_m,branch,enter_time_s,restart_time_s,trapping_time_s\n";
    for (const auto& v : r.pore_visits) {
      const auto& p = r.pores[v.pore];
      out << v.pore << ',' << num(p.x) << ',' << num(p.y) << ',' << num(p.radius) << ',' << v.branch << ','
          << num(v.enter_time) << ',' << num(v.restart_time) << ',' << num(v.trapping_time) << '\n';
    }
  });
}

void write_summary_json(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    const auto all = speed_stats(r.speeds);
    out << "{\n";
    out << "  \"tool\": " << quoted(std::string("pd-post ") + pd::version_string) << ",\n";
    out << "  \"input\": " << quoted(r.data.path) << ",\n";
    out << "  \"damage_threshold\": " << num(r.data.threshold) << ",\n";
    out << "  \"rayleigh_speed_m_per_s\": " << num(r.rayleigh_speed) << ",\n";
    out << "  \"material\": {\"youngs_modulus_Pa\": " << num(r.data.youngs_modulus)
        << ", \"density_kg_per_m3\": " << num(r.data.density)
        << ", \"material_poisson_ratio\": " << num(r.data.material_poisson_ratio) << "},\n";
    out << "  \"time_step_s\": " << num(r.data.time_step) << ",\n";
    out << "  \"window\": {\"steps\": " << r.window_steps << ", \"seconds\": " << num(r.window_seconds) << "},\n";
    out << "  \"max_speed_m_per_s\": " << num(all.max) << ",\n";
    out << "  \"mean_speed_m_per_s\": " << num(all.mean) << ",\n";
    out << "  \"max_speed_over_rayleigh\": " << num(all.max / r.rayleigh_speed) << ",\n";
    out << "  \"mean_speed_over_rayleigh\": " << num(all.mean / r.rayleigh_speed) << ",\n";
    out << "  \"branches\": [";
    for (std::size_t b = 0; b < r.network.branches.size(); ++b) {
      const auto& br = r.network.branches[b];
      const auto st = speed_stats(r.speeds, br.id);
      out << (b ? "," : "") << "\n    {\"branch\": " << br.id << ", \"parent\": " << br.parent
          << ", \"start_time_s\": " << num(br.start_time) << ", \"start_x_m\": " << num(br.origin_x)
          << ", \"start_y_m\": " << num(br.origin_y) << ", \"end_time_s\": " << num(br.end_time)
          << ", \"end_x_m\": " << num(r.tips[b].x.back()) << ", \"end_y_m\": " << num(r.tips[b].y.back())
          << ", \"length_m\": " << num(tip_path_length(r.tips[b])) << ", \"particles\": " << br.particles.size()
          << ", \"max_speed_m_per_s\": " << num(st.max) << ", \"mean_speed_m_per_s\": " << num(st.mean) << "}";
    }
    out << "\n  ],\n  \"branching_events\": [";
    for (std::size_t e = 0; e < r.network.branchings.size(); ++e) {
      const auto& ev = r.network.branchings[e];
      out << (e ? "," : "") << "\n    {\"time_s\": " << num(ev.time) << ", \"x_m\": " << num(ev.x)
          << ", \"y_m\": " << num(ev.y) << ", \"parent\": " << ev.parent << ", \"children\": [";
      for (std::size_t c = 0; c < ev.children.size(); ++c) out << (c ? ", " : "") << ev.children[c];
      out << "], \"angle_deg\": " << num(ev.angle_deg) << "}";
    }
    out << "\n  ],\n  \"pores\": {\"source\": " << quoted(r.pore_source) << ", \"circles\": [";
    for (std::size_t p = 0; p < r.pores.size(); ++p)
      out << (p ? ", " : "") << "[" << num(r.pores[p].x) << ", " << num(r.pores[p].y) << ", "
          << num(r.pores[p].radius) << "]";
    out << "]},\n  \"pore_trapping\": [";
    for (std::size_t v = 0; v < r.pore_visits.size(); ++v) {
      const auto& pv = r.pore_visits[v];
      out << (v ? "," : "") << "\n    {\"pore\": " << pv.pore << ", \"branch\": " << pv.branch
          << ", \"enter_time_s\": " << num(pv.enter_time)
          << ", \"restart_time_s\": " << (pv.restart_time >= 0 ? num(pv.restart_time) : "null")
          << ", \"trapping_time_s\": " << (pv.trapping_time >= 0 ? num(pv.trapping_time) : "null")
          << ", \"restarted_beyond_pore\": " << (pv.jumped ? "true" : "false") << "}";
    }
    out << "\n  ],\n  \"pictures\": [";
    for (std::size_t p = 0; p < r.pictures.size(); ++p) out << (p ? ", " : "") << quoted(r.pictures[p]);
    out << "],\n  \"notes\": [";
    for (std::size_t n = 0; n < r.notes.size(); ++n) out << (n ? ", " : "") << quoted(r.notes[n]);
    out << "]\n}\n";
  });
}

}  // namespace pd::post
