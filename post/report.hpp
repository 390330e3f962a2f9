#pragma once
// The tables (CSV) and summary.json of a post directory for a dynamic run,
// written atomically. The JSON helpers are shared with the quasi-static report.
#include <ostream>
#include <string>
#include <vector>

#include "json_text.hpp"  // json_string
#include "post_pipeline.hpp"

namespace pd::post {

// Numbers and strings are pd::json_number's and pd::json_string's (json_text.hpp).
using pd::json_number;
// ["a", "b"]
std::string json_strings(const std::vector<std::string>& list);
// The line_profile entry of summary.json.
std::string line_profile_json(const SampleLine& line, double offset, const std::vector<LineSample>& samples);

// The end of summary.json, the same for dynamic and quasi-static results (any
// Result with line_segment, line_offset, line, pictures, warnings, notes): the
// line profile if one was asked for, the lists, and the closing brace.
template <class Result>
void write_summary_tail(std::ostream& out, const Result& r) {
  if (r.line_segment)
    out << "  \"line_profile\": " << line_profile_json(*r.line_segment, r.line_offset, r.line) << ",\n";
  out << "  \"pictures\": " << json_strings(r.pictures) << ",\n";
  out << "  \"warnings\": " << json_strings(r.warnings) << ",\n";
  out << "  \"notes\": " << json_strings(r.notes) << "\n}\n";
}

void write_tip_table(const std::string& path, const PostResult& r);      // crack_tips.csv
void write_speed_table(const std::string& path, const PostResult& r);    // crack_speed.csv
void write_branch_table(const std::string& path, const PostResult& r);   // branches.csv
void write_pore_table(const std::string& path, const PostResult& r);     // pore_trapping.csv
void write_branching_table(const std::string& path, const PostResult& r);  // branching_events.csv
void write_summary_json(const std::string& path, const PostResult& r);   // summary.json

}  // namespace pd::post
