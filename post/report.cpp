#include "report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "atomic_file.hpp"
#include "pd/version.hpp"

namespace pd::post {

std::string json_strings(const std::vector<std::string>& list) {
  std::string out = "[";
  for (std::size_t i = 0; i < list.size(); ++i) out += (i ? ", " : "") + json_string(list[i]);
  return out + "]";
}

namespace {
const auto num = json_number;
const auto quoted = json_string;
}  // namespace

std::string line_profile_json(const SampleLine& line, double offset, const std::vector<LineSample>& samples) {
  std::size_t jumps = 0;
  for (const auto& s : samples) jumps += s.has_jump ? 1 : 0;
  return "{\"from_m\": [" + num(line.x0) + ", " + num(line.y0) + "], \"to_m\": [" + num(line.x1) + ", " +
         num(line.y1) + "], \"offset_m\": " + num(offset) + ", \"samples\": " + std::to_string(samples.size()) +
         ", \"samples_with_jump\": " + std::to_string(jumps) + ", \"table\": \"line_profile.csv\"}";
}

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
          << num(tip.y.back()) << ',' << num(tip_path_length(tip, 2 * r.data.horizon)) << '\n';
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

void write_branching_table(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "time_s,x_m,y_m,parent,children,angle_deg,angle_length_m,near_angle_deg\n";
    for (const auto& e : r.network.branchings) {
      std::string children;
      for (std::size_t c = 0; c < e.children.size(); ++c) children += (c ? ";" : "") + std::to_string(e.children[c]);
      out << num(e.time) << ',' << num(e.x) << ',' << num(e.y) << ',' << e.parent << ',' << children << ','
          << num(e.angle_deg) << ',' << num(e.angle_length) << ',' << num(e.near_angle_deg) << '\n';
    }
  });
}

void write_summary_json(const std::string& path, const PostResult& r) {
  write_atomically(path, [&](std::ofstream& out) {
    const auto all = speed_stats(r.speeds);
    out << "{\n";
    out << "  \"tool\": " << quoted(std::string("pd-post ") + pd::version_string) << ",\n";
    out << "  \"mode\": \"dynamic\",\n";
    out << "  \"input\": " << quoted(r.data.path) << ",\n";
    out << "  \"run\": {\"complete\": " << (r.solver.present ? "true" : "false")
        << ", \"solver_summary\": " << (r.solver.present ? quoted(r.solver.path) : "null")
        << ", \"stop_reason\": " << (r.solver.stop_reason.empty() ? "null" : quoted(r.solver.stop_reason))
        << ", \"end_time_s\": " << num(r.data.end_time)
        << ", \"end_step\": " << (r.data.end_step >= 0 ? std::to_string(r.data.end_step) : "null") << "},\n";
    out << "  \"damage_threshold\": " << num(r.data.threshold) << ",\n";
    out << "  \"max_damage\": " << num(r.max_damage) << ",\n";
    out << "  \"rayleigh_speed_m_per_s\": " << num(r.rayleigh_speed) << ",\n";
    out << "  \"rayleigh_speed\": {\"m_per_s\": " << num(r.rayleigh.speed)
        << ", \"formula\": " << quoted(rayleigh_formula) << ", \"plane\": " << quoted(to_string(r.model.plane))
        << ", \"plane_source\": " << quoted(r.model.plane_source)
        << ", \"poisson_ratio\": " << num(r.model.poisson_ratio)
        << ", \"poisson_ratio_source\": " << quoted(r.model.poisson_ratio_source)
        << ", \"in_plane_poisson_ratio\": " << num(r.rayleigh.in_plane_poisson_ratio)
        << ", \"shear_speed_m_per_s\": " << num(r.rayleigh.shear_speed)
        << ", \"ratio_to_shear_speed\": " << num(r.rayleigh.ratio)
        << ", \"with_material_poisson_ratio_m_per_s\": "
        << (r.material_rayleigh ? num(r.material_rayleigh->speed) : "null") << "},\n";
    out << "  \"material\": {\"youngs_modulus_Pa\": " << num(r.data.youngs_modulus)
        << ", \"density_kg_per_m3\": " << num(r.data.density)
        << ", \"model_poisson_ratio\": " << num(r.model.poisson_ratio)
        << ", \"material_poisson_ratio\": "
        << (r.data.material_poisson_ratio ? num(*r.data.material_poisson_ratio) : "null") << "},\n";
    out << "  \"time_step_s\": " << num(r.data.time_step) << ",\n";
    char rule[200];
    std::snprintf(rule, sizeof rule, "the time a tip at c_R needs to cross %g cells of the spacing: ceil(%g dx / (c_R dt))",
                  window_cells_at_rayleigh, window_cells_at_rayleigh);
    out << "  \"window\": {\"steps\": " << r.window_steps << ", \"seconds\": " << num(r.window_seconds)
        << ", \"requested\": " << (r.window.requested ? "true" : "false")
        << ", \"rule_steps\": " << r.window.rule_steps << ", \"rule\": " << quoted(rule)
        << ", \"cells_crossed_at_rayleigh_speed\": " << num(r.window.cells_at_rayleigh) << "},\n";
    out << "  \"branching_angle_length_m\": " << num(r.angle_length) << ",\n";
    // A speed over no window is unknown (null), not 0 m/s.
    const auto speed = [](const SpeedStats& st, double value) { return st.samples ? num(value) : std::string("null"); };
    out << "  \"max_speed_m_per_s\": " << speed(all, all.max) << ",\n";
    out << "  \"mean_speed_m_per_s\": " << speed(all, all.mean) << ",\n";
    out << "  \"max_speed_over_rayleigh\": " << speed(all, all.max / r.rayleigh_speed) << ",\n";
    out << "  \"mean_speed_over_rayleigh\": " << speed(all, all.mean / r.rayleigh_speed) << ",\n";
    out << "  \"branches\": [";
    for (std::size_t b = 0; b < r.network.branches.size(); ++b) {
      const auto& br = r.network.branches[b];
      const auto st = speed_stats(r.speeds, br.id);
      out << (b ? "," : "") << "\n    {\"branch\": " << br.id << ", \"parent\": " << br.parent
          << ", \"start_time_s\": " << num(br.start_time) << ", \"start_x_m\": " << num(br.origin_x)
          << ", \"start_y_m\": " << num(br.origin_y) << ", \"end_time_s\": " << num(br.end_time)
          << ", \"end_x_m\": " << num(r.tips[b].x.back()) << ", \"end_y_m\": " << num(r.tips[b].y.back())
          << ", \"length_m\": " << num(tip_path_length(r.tips[b], 2 * r.data.horizon)) << ", \"particles\": " << br.particles.size()
          << ", \"joined_groups\": " << br.joined_groups
          << ", \"max_speed_m_per_s\": " << speed(st, st.max) << ", \"mean_speed_m_per_s\": " << speed(st, st.mean)
          << "}";
    }
    out << "\n  ],\n  \"damage_spots\": [";
    for (std::size_t k = 0; k < r.network.spots.size(); ++k) {
      const auto& spot = r.network.spots[k];
      out << (k ? ", " : "") << "{\"time_s\": " << num(spot.time) << ", \"x_m\": " << num(spot.x)
          << ", \"y_m\": " << num(spot.y) << ", \"particles\": " << spot.particles << "}";
    }
    out << "],\n  \"branching_events\": [";
    for (std::size_t e = 0; e < r.network.branchings.size(); ++e) {
      const auto& ev = r.network.branchings[e];
      out << (e ? "," : "") << "\n    {\"time_s\": " << num(ev.time) << ", \"x_m\": " << num(ev.x)
          << ", \"y_m\": " << num(ev.y) << ", \"parent\": " << ev.parent << ", \"children\": [";
      for (std::size_t c = 0; c < ev.children.size(); ++c) out << (c ? ", " : "") << ev.children[c];
      out << "], \"angle_deg\": " << num(ev.angle_deg) << ", \"angle_length_m\": " << num(ev.angle_length)
          << ", \"fit_lengths_m\": [";
      for (std::size_t c = 0; c < ev.fit_lengths.size(); ++c) out << (c ? ", " : "") << num(ev.fit_lengths[c]);
      out << "], \"near_angle_deg\": " << num(ev.near_angle_deg) << "}";
    }
    out << "\n  ],\n  \"pores\": {\"source\": " << quoted(r.pore_source) << ", \"circles\": [";
    for (std::size_t p = 0; p < r.pores.size(); ++p)
      out << (p ? ", " : "") << "[" << num(r.pores[p].x) << ", " << num(r.pores[p].y) << ", "
          << num(r.pores[p].radius) << "]";
    // The pores (by their index, as in pore_trapping) measured by their outline.
    out << "], \"by_outline\": [";
    bool first = true;
    for (std::size_t p = 0; p < r.pores.size(); ++p)
      if (r.pores[p].has_outline()) out << (first ? "" : ", ") << p, first = false;
    out << "]},\n  \"pore_trapping\": [";
    for (std::size_t v = 0; v < r.pore_visits.size(); ++v) {
      const auto& pv = r.pore_visits[v];
      out << (v ? "," : "") << "\n    {\"pore\": " << pv.pore << ", \"branch\": " << pv.branch
          << ", \"enter_time_s\": " << num(pv.enter_time)
          << ", \"restart_time_s\": " << (pv.restart_time >= 0 ? num(pv.restart_time) : "null")
          << ", \"trapping_time_s\": " << (pv.trapping_time >= 0 ? num(pv.trapping_time) : "null")
          << ", \"restarted_beyond_pore\": " << (pv.jumped ? "true" : "false") << "}";
    }
    out << "\n  ],\n";
    if (r.comparison) {
      const auto& c = *r.comparison;
      out << "  \"comparison\": {\"reference\": " << quoted(c.reference) << ", \"band_m\": " << num(c.band)
          << ", \"damage_level\": " << num(c.damage_level) << ", \"reference_damaged\": " << c.reference_damaged
          << ", \"damaged\": " << c.damaged << ", \"damaged_outside_band\": " << c.outside
          << ", \"area_outside_band_m2\": " << num(c.area_outside) << "},\n";
    }
    out << "  \"maps\": [";
    for (std::size_t m = 0; m < r.maps.size(); ++m)
      out << (m ? ", " : "") << "{\"requested_time_s\": " << num(r.maps[m].requested)
          << ", \"time_s\": " << num(r.maps[m].used) << ", \"source\": " << quoted(r.maps[m].source) << "}";
    out << "],\n";
    write_summary_tail(out, r);
  });
}

}  // namespace pd::post
