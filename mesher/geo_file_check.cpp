#include "geo_file_check.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <vector>

#include "error.hpp"

namespace pd {

namespace {

struct Token {
  enum Kind { word, number, text, symbol } kind;
  std::string value;
  int line;
};

// gmsh's lexer in brief (Parser/Gmsh.l): // and /* */ comments, strings in
// double or single quotes without escapes, words [A-Za-z_][A-Za-z0-9_]*.
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> tokens;
  int line = 1;
  std::size_t i = 0;
  const auto advance = [&](std::size_t to) {
    line += static_cast<int>(std::count(s.begin() + static_cast<std::ptrdiff_t>(i), s.begin() + static_cast<std::ptrdiff_t>(to), '\n'));
    i = to;
  };
  while (i < s.size()) {
    const char c = s[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      advance(i + 1);
    } else if (s.compare(i, 2, "//") == 0) {
      advance(std::min(s.size(), s.find('\n', i) == std::string::npos ? s.size() : s.find('\n', i)));
    } else if (s.compare(i, 2, "/*") == 0) {
      const auto end = s.find("*/", i + 2);
      advance(end == std::string::npos ? s.size() : end + 2);
    } else if (c == '"' || c == '\'') {
      const auto end = s.find(c, i + 1);
      const int at = line;
      const std::size_t stop = end == std::string::npos ? s.size() : end;
      tokens.push_back({Token::text, s.substr(i + 1, stop - i - 1), at});
      advance(end == std::string::npos ? s.size() : end + 1);
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t end = i;
      while (end < s.size() && (std::isalnum(static_cast<unsigned char>(s[end])) || s[end] == '_')) ++end;
      tokens.push_back({Token::word, s.substr(i, end - i), line});
      advance(end);
    } else if (std::isdigit(static_cast<unsigned char>(c))) {
      std::size_t end = i;
      while (end < s.size() && (std::isalnum(static_cast<unsigned char>(s[end])) || s[end] == '.')) ++end;
      tokens.push_back({Token::number, s.substr(i, end - i), line});
      advance(end);
    } else {
      // Two-character operators matter here only for '>>' (append to a file)
      // and the compound assignments ('+=' ...) that mark a variable.
      static const char* pairs[] = {">>", "+=", "-=", "*=", "/=", "==", "!=", "<=", ">=", "<<", "||", "&&", "++", "--", "::"};
      std::string op(1, c);
      for (const char* p : pairs)
        if (s.compare(i, 2, p) == 0) op = p;
      tokens.push_back({Token::symbol, op, line});
      advance(i + op.size());
    }
  }
  return tokens;
}

bool is_cad_file_name(std::string name) {
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* ext : {".step", ".stp", ".brep", ".brp", ".iges", ".igs", ".xao"})
    if (name.size() > std::string(ext).size() && name.compare(name.size() - std::string(ext).size(), std::string::npos, ext) == 0)
      return true;
  return false;
}

}  // namespace

namespace {
std::string file_text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw file_error(file, "cannot read geometry file");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}


std::vector<std::pair<std::string, int>> physical_curve_names(const std::vector<Token>& tokens) {
  std::vector<std::pair<std::string, int>> names;
  for (std::size_t k = 0; k + 3 < tokens.size(); ++k)
    if (tokens[k].kind == Token::word && tokens[k].value == "Physical" && tokens[k + 1].kind == Token::word &&
        (tokens[k + 1].value == "Curve" || tokens[k + 1].value == "Line") && tokens[k + 2].value == "(" &&
        tokens[k + 3].kind == Token::text)
      names.push_back({tokens[k + 3].value, tokens[k + 3].line});
  return names;
}
}  // namespace

std::vector<std::pair<std::string, int>> check_geometry_file_is_data(const std::string& file) {
  if (is_cad_file_name(file)) return {};
  const std::string text = file_text(file);
  // A file cut to nothing (a failed copy or download) was told it has no
  // plane surface before 7 December 2026, as if it were a geometry without one.
  if (text.find_first_not_of(" \t\r\n\f\v") == std::string::npos)
    throw file_error(file, std::string(text.empty() ? "the file is empty (0 bytes)" : "the file holds only white space") +
                               ": a geometry file defines the plate (its points, curves, curve loops and one Plane "
                               "Surface; docs/mesher.md, \"Geometry input\"); was it cut short when copied?");
  // Control characters other than white space: not a script gmsh should read.
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if ((byte < 0x20 && !std::isspace(byte)) || byte == 0x7f) {
      char where[120];
      std::snprintf(where, sizeof where, "not a text file (byte 0x%02x at offset %zu, line %ld)", byte, i,
                    1 + static_cast<long>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(i), '\n')));
      throw file_error(file, std::string(where) + "; pd-mesh reads gmsh .geo scripts or CAD files (.step, .brep, ...)");
    }
  }
  const auto tokens = tokenize(text);

  // Words that make gmsh act outside the geometry, and what they would do.
  static const std::map<std::string, std::string> refused = {
      {"SystemCall", "runs a shell command"},
      {"System", "runs a shell command"},
      {"NonBlockingSystemCall", "runs a shell command"},
      {"OnelabRun", "runs another program"},
      {"OnelabAction", "talks to other programs"},
      {"Include", "runs another script, which pd-mesh has not checked (copy its content into this file)"},
      {"Save", "writes a file"},
      {"Print", "writes a file"},
      {"CreateDir", "creates a directory"},
      {"Exit", "ends the process"},
      {"Abort", "stops reading the file part way"},
      {"Sleep", "makes gmsh wait"},
      {"Plugin", "runs a gmsh plugin"},
      {"Merge", "reads another file (only CAD files such as .step or .brep, named by a plain string, are accepted)"},
      {"MergeWithBoundingBox", "reads another file (only CAD files such as .step or .brep, named by a plain string, are accepted)"},
      {"ShapeFromFile", "reads another file (only CAD files such as .step or .brep, named by a plain string, are accepted)"},
  };
  static const std::vector<std::string> marks_a_variable = {"=", "+=", "-=", "*=", "/=", "[", "~", ".", "++", "--"};
  const auto fail = [&](const Token& t, const std::string& what) {
    throw Error(file + ":" + std::to_string(t.line) + ": '" + t.value + "' " + what +
                "; a geometry file may only describe geometry, so pd-mesh refuses it before gmsh reads the file");
  };
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    const auto& t = tokens[k];
    if (t.kind != Token::word) continue;
    const Token* next = k + 1 < tokens.size() ? &tokens[k + 1] : nullptr;
    const bool variable = next && next->kind == Token::symbol &&
                          std::find(marks_a_variable.begin(), marks_a_variable.end(), next->value) != marks_a_variable.end();
    if ((t.value == "Printf" || t.value == "Sprintf") && next && next->value == "(") {
      // Printf(...) > "file" and >> "file" write to a file.
      int depth = 0;
      std::size_t j = k + 1;
      for (; j < tokens.size(); ++j) {
        if (tokens[j].kind != Token::symbol) continue;
        if (tokens[j].value == "(") ++depth;
        if (tokens[j].value == ")" && --depth == 0) break;
      }
      if (j + 1 < tokens.size() && (tokens[j + 1].value == ">" || tokens[j + 1].value == ">>"))
        fail(t, "with '" + tokens[j + 1].value + "' writes to a file");
      continue;
    }
    const auto found = refused.find(t.value);
    if (found == refused.end() || (variable && t.value != "Exit" && t.value != "Abort")) continue;
    const bool reads_file = t.value == "Merge" || t.value == "MergeWithBoundingBox" || t.value == "ShapeFromFile";
    // Merge "part.step"; and ShapeFromFile("part.step") read CAD data.
    const auto text_at = [&](std::size_t j) { return j < tokens.size() && tokens[j].kind == Token::text; };
    const auto value_at = [&](std::size_t j) { return j < tokens.size() ? tokens[j].value : std::string(); };
    if (reads_file && text_at(k + 1) && is_cad_file_name(value_at(k + 1)) && value_at(k + 2) == ";") continue;
    if (reads_file && value_at(k + 1) == "(" && text_at(k + 2) && is_cad_file_name(value_at(k + 2)) &&
        value_at(k + 3) == ")")
      continue;
    fail(t, found->second);
  }
  // gmsh runs a file that ends inside a loop or a condition without a word
  // (a .geo cut short after 'For k In {1:8}' meshed the plate without the
  // holes the loop was to make): a block left open is refused, naming it.
  static const std::map<std::string, std::string> closes = {{"For", "EndFor"}, {"If", "EndIf"},
                                                            {"Macro", "Return"}, {"Function", "Return"}};
  std::vector<const Token*> open;
  for (const auto& t : tokens) {
    if (t.kind != Token::word) continue;
    if (closes.count(t.value)) open.push_back(&t);
    else if (!open.empty() && closes.at(open.back()->value) == t.value) open.pop_back();
  }
  if (!open.empty())
    throw Error(file + ":" + std::to_string(open.back()->line) + ": '" + open.back()->value + "' has no '" +
                closes.at(open.back()->value) +
                "' before the file ends: was the file cut short? gmsh would run it without the rest of the block; "
                "give the whole file");
  return physical_curve_names(tokens);
}

GeometryStatements geometry_statements(const std::string& file) {
  GeometryStatements r;
  if (is_cad_file_name(file)) return r;
  const auto tokens = tokenize(file_text(file));
  // An assignment: a word followed by '=' that is not an option's last part
  // ('General.Terminal = 0') nor a key inside a list ('DefineConstant[ R = ...').
  const auto sets = [&](std::size_t k) {
    return tokens[k].kind == Token::word && k + 1 < tokens.size() && tokens[k + 1].value == "=" &&
           (k == 0 || tokens[k - 1].value == ";" || tokens[k - 1].kind == Token::word);
  };
  std::map<std::string, std::pair<int, int>> seen;  // name -> (line first set, words that read it)
  std::vector<std::string> order;
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    if (tokens[k].value == ";" && tokens[k].kind == Token::symbol) r.last_statement_line = tokens[k].line;
    if (tokens[k].kind != Token::word) continue;
    if (tokens[k].value == "SetFactory" && k + 2 < tokens.size() && tokens[k + 2].kind == Token::text &&
        tokens[k + 2].value == "OpenCASCADE")
      r.opencascade = true;
    if (tokens[k].value == "BooleanDifference" && !sets(k)) {
      if (r.first_difference_line == 0) r.first_difference_line = tokens[k].line;
      // Its two brace blocks, objects then tools: whether each says Delete.
      std::size_t j = k + 1;
      for (int block = 0; block < 2; ++block) {
        while (j < tokens.size() && tokens[j].value != "{" && tokens[j].value != ";") ++j;
        if (j >= tokens.size() || tokens[j].value != "{") break;
        bool deletes = false;
        int depth = 0;
        for (; j < tokens.size(); ++j) {
          if (tokens[j].kind == Token::symbol && tokens[j].value == "{") ++depth;
          if (tokens[j].kind == Token::symbol && tokens[j].value == "}" && --depth == 0) break;
          deletes = deletes || (depth == 1 && tokens[j].kind == Token::word && tokens[j].value == "Delete");
        }
        int& keeping = block == 0 ? r.difference_keeping_objects_line : r.difference_keeping_tools_line;
        if (!deletes && keeping == 0) keeping = tokens[k].line;
        ++j;
      }
    }
    if (sets(k)) {
      if (seen.emplace(tokens[k].value, std::make_pair(tokens[k].line, 0)).second) order.push_back(tokens[k].value);
      continue;
    }
    auto& entry = seen[tokens[k].value];  // (a word read before it is set counts too)
    ++entry.second;
  }
  for (const auto& name : order)
    if (seen[name].second == 0) r.unread_names.push_back({name, seen[name].first});
  return r;
}

}  // namespace pd
