#pragma once
// A geometry file is data. gmsh's .geo language can also run shell commands
// (SystemCall), other programs (OnelabRun), other scripts (Include), write
// files (Save, Print, Printf > file, CreateDir) and end the process (Exit),
// all as the user who runs pd-mesh. Such statements are refused before gmsh
// reads the file. (Long-running loops are bounded by GmshSession's time limit.)
#include <string>
#include <utility>
#include <vector>

namespace pd {

// Throws pd::Error "FILE:LINE: 'WORD' ..." for the first statement that is
// not geometry. Comments and strings are skipped as gmsh's lexer does; a
// word used as a variable name (followed by '=', '[', '~', '.', ...) is
// fine. Files that gmsh reads as CAD data (.step, .stp, .brep, .iges, .igs,
// .xao) are not scripts and are not scanned.
// A file with a control character (a binary file given by mistake) is
// refused too: "not a text file", rather than gmsh's errors full of raw bytes.
// Returns the names the file gives physical curve groups ('Physical
// Curve("grip") = ...' or 'Physical Line'), each with its line; none for a
// CAD file. gmsh drops a group whose curves do not exist without a word: the
// names it lost are those of this list it does not have.
std::vector<std::pair<std::string, int>> check_geometry_file_is_data(const std::string& file);

// What a geometry file sets and never reads, and where it cuts: the names
// given a value at the start of a statement ('R = 0.75;'; not options such as
// 'Mesh.Algorithm =') that no other word of the file reads, each with the
// line it is set on; the line of the file's last statement; the line of its
// first BooleanDifference (0: none). A file cut short after its outer
// boundary keeps the numbers meant for its holes unread; a difference whose
// tools miss the plate leaves it whole. Nothing for a CAD file.
struct GeometryStatements {
  std::vector<std::pair<std::string, int>> unread_names;
  int last_statement_line = 0;
  int first_difference_line = 0;
  // The line of the first BooleanDifference without 'Delete' among its
  // objects (it keeps the surface it cuts from), or among its tools (it keeps
  // the surfaces it cuts out); 0: none.
  int difference_keeping_objects_line = 0, difference_keeping_tools_line = 0;
  // Whether the file switches to the OpenCASCADE kernel (SetFactory("OpenCASCADE")).
  bool opencascade = false;
};
GeometryStatements geometry_statements(const std::string& file);

}  // namespace pd
