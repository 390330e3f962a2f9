#pragma once
// The tables (CSV) and summary.json of a post directory, written atomically.
#include <string>

#include "post_pipeline.hpp"

namespace pd::post {

void write_tip_table(const std::string& path, const PostResult& r);      // crack_tips.csv
void write_speed_table(const std::string& path, const PostResult& r);    // crack_speed.csv
void write_branch_table(const std::string& path, const PostResult& r);   // branches.csv
void write_pore_table(const std::string& path, const PostResult& r);     // pore_trapping.csv
void write_summary_json(const std::string& path, const PostResult& r);   // summary.json

}  // namespace pd::post
