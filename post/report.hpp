#pragma once
// The tables (CSV) and summary.json of a post directory for a dynamic run,
// written atomically. The JSON helpers are shared with the quasi-static report.
#include <string>
#include <vector>

#include "post_pipeline.hpp"

namespace pd::post {

// A JSON number (%.9g; null if not finite) and a quoted JSON string.
std::string json_number(double v);
std::string json_string(const std::string& s);
// ["a", "b"]
std::string json_strings(const std::vector<std::string>& list);
// The line_profile entry of summary.json.
std::string line_profile_json(const SampleLine& line, double offset, const std::vector<LineSample>& samples);

void write_tip_table(const std::string& path, const PostResult& r);      // crack_tips.csv
void write_speed_table(const std::string& path, const PostResult& r);    // crack_speed.csv
void write_branch_table(const std::string& path, const PostResult& r);   // branches.csv
void write_pore_table(const std::string& path, const PostResult& r);     // pore_trapping.csv
void write_branching_table(const std::string& path, const PostResult& r);  // branching_events.csv
void write_summary_json(const std::string& path, const PostResult& r);   // summary.json

}  // namespace pd::post
