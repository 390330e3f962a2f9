#pragma once
// Atomic output: write to a temporary file next to the result, check that all
// of it reached the disk, then rename it onto the result. A crash, a kill or
// a full disk leaves at most a temporary file, never a truncated result under
// the final name. Temporary names: "NAME.tmp.PID" (write_atomically) and
// ".tmp.PID.NAME" (write_atomically_via, which keeps the extension last).
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace pd {

// Calls `write` with a binary output stream on a temporary file next to
// `path`, checks the stream after closing it (every byte written, none lost
// to a full disk), checks the file's size against the bytes the stream took,
// flushes it to disk and renames it onto `path`. On any failure the temporary
// file is removed, `path` is left as it was, and pd::Error names `path`.
void write_atomically(const std::string& path, const std::function<void(std::ofstream&)>& write);

// Same for writers that want a file name (e.g. VTK writers): `write` must
// create the file at the given temporary path and throw if its writer reports
// a failure (VTK writers report through their error code, not by throwing).
// The file must exist, be non-empty and reach the disk before the rename.
void write_atomically_via(const std::string& path,
                          const std::function<void(const std::string& temporary_path)>& write);

// Creates the folder that `path` will be written into, with its parents,
// where it is missing (a tool's output named before its work starts, so that
// a long run does not fail at its end for want of a folder). Throws pd::Error
// naming `path` if the folder cannot be made (e.g. a file has its name).
// Returns the folders it made, outermost first, for remove_made_folders.
std::vector<std::string> create_folder_for(const std::string& path);

// Takes back folders create_folder_for made when a later step fails, so that
// a failed command leaves no empty folder behind; a folder that holds
// anything stays.
void remove_made_folders(const std::vector<std::string>& made);

// The outermost folder of `folder` that does not exist yet (the folder
// itself, or the first missing one of its parents), absolute; empty when it
// exists: what making it makes, and what a run that fails takes back. A
// link that leads nowhere exists: the user's.
std::string outermost_missing_folder(const std::string& folder);

// Refuses, before a tool starts its work, a path the system cannot use at
// all: longer than PATH_MAX or with a name longer than NAME_MAX, a loop of
// symbolic links. pd::Error "OPTION PATH: File name too long; give a shorter
// path" (`option` such as "-o"; empty for a positional argument), the path
// clipped to one line. A path that does not exist yet passes, unless it
// begins or ends with white space (`-o "plate.pdp "`): "OPTION 'PATH': the
// name ends in a space, and no file or folder has that name: give it without, OPTION
// TRIMMED" (a name with such white space that exists passes); so does a
// folder of the path that names nothing (`-o "out /x.pdp"`): "OPTION 'PATH':
// its part 'out ' ends in a space, and no folder or file has that name (the
// folder out, without it, exists): give it without, OPTION out/x.pdp" (the
// note in brackets where that folder exists; where the path without the
// white space exists, it is named instead).
void check_usable_path(const std::string& path, const std::string& option);

// The reason check_usable_path gives, with what to do ("Too many levels of
// symbolic links: a symbolic link on the path leads back to itself, ...;
// mend or remove the link, or give a path without it"), for a path an input
// file's key gives (a scene's particles); empty where the system can use it
// (or it does not exist: the caller's own message).
std::string unusable_path_reason(const std::string& path);

// The warning for a name that begins or ends with white space and names a
// file or folder that exists (`-o "run "` where the folder "run " exists):
// taken, as it is real, but the space is unseen in a listing and in every
// message that quotes the name. "OPTION 'PATH': the name ends in a space;
// the folder of that name exists and is used (run, without it, is another
// name)"; empty for any other name.
std::string white_space_name_warning(const std::string& path, const std::string& option);

// The rule of both for a name a key of an input file gives (a scene's
// particles = "plate.pdp "), read against `folder` (its file's folder; ""
// for the working directory; an absolute name as it is). `label` begins the
// message ("scene.toml: key 'particles' = 'plate.pdp '"), `given_as` writes
// a name as the key takes it ('particles = "plate.pdp"'). Where nothing has
// the name, pd::Error "LABEL: the name ends in a space, and no file or folder
// has that name (plate.pdp, without it, exists): give it without, GIVEN_AS";
// where something has it, the warning "LABEL: the name ends in a space; the
// file of that name exists and is used (plate.pdp, without it, is another
// name)"; "" for a name without white space at its ends. A folder of the
// name with white space at its ends that names nothing is refused as
// check_usable_path refuses it ("LABEL: its part 'out ' ends in a space,
// ..., give it without, GIVEN_AS").
std::string white_space_name_check(const std::string& name, const std::string& folder, const std::string& label,
                                   const std::function<std::string(const std::string&)>& given_as);

// Refuses a result path that names something other than a file: a folder,
// a device (/dev/null), a FIFO or a socket. The atomic rename would put the
// result in its place (run as root, over /dev/null itself). A symbolic link
// passes: the rename replaces the link, not what it points to. pd::Error
// "OPTION PATH: is a device, not a file ..." (`option` empty: "PATH: ...").
// A path that does not exist passes. `advice`, if given, says what to do
// instead of "name a file" (for a result whose name the tool chooses).
void check_replaceable_file(const std::string& path, const std::string& option, const std::string& advice = "");

// The absolute form of `path` with "..", "." and symbolic links resolved
// (lexically where it does not exist yet), without a trailing separator.
std::string resolved_path(const std::string& path);

// Why a file cannot be made in `folder` (an existing folder), found by making
// one (".write_test.tmp.PID") and removing it: the system's reason, e.g.
// "Permission denied" for a read-only folder; empty if it can. Permission
// bits alone would not say (a file system mounted read-only, /proc, root).
std::string why_cannot_write_in(const std::string& folder);

// Refuses, before a tool's work, a result path whose folder the tool could
// not write in; where the folder is missing, the nearest folder of the path
// that exists, in which the missing ones would be made. pd::Error "OPTION
// PATH: cannot write in its folder FOLDER: REASON". A path whose nearest
// existing part is not a folder (a file) is refused too: "OPTION PATH:
// cannot make its folder FOLDER: PART is a file, ...".
void check_writable_folder_for(const std::string& path, const std::string& option);

// Whether two paths name the same file or folder (existing or not): their
// resolved_path forms compared.
bool same_path(const std::string& a, const std::string& b);

// Whether `inner` is the folder `outer` or lies inside it (existing or not),
// compared as same_path compares.
bool path_within(const std::string& inner, const std::string& outer);

// Removes the temporary files that writers of killed runs left in `folder`
// (not in its subfolders): regular files named "NAME.tmp.PID" or
// ".tmp.PID.NAME" whose PID is not a running process, or is this process's
// own (call it before this process writes into the folder). Files of another
// running process are kept: it may be writing them. Returns the names removed.
// A folder that does not exist has nothing to remove. Throws pd::Error naming
// the file if one cannot be removed.
std::vector<std::string> remove_stale_temporaries(const std::string& folder);

// Hash of a file's bytes (the particle-file checksum function), for provenance.
std::string file_hash_hex(const std::string& path);

}  // namespace pd
