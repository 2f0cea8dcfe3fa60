// The editor's autosaves (data, no UI): one script per editor launch in the
// autosave directory, named by the session's input and start time and the
// process id ("bunny-20261202-040312-4711.anisurf"). A launch writes only its
// own file (created exclusively: an existing name is never taken over), so
// an earlier launch's autosave stays as it was until it is restored or
// pruned. Restoring replays the script's edits but not its `save`,
// `screenshot` and `quit` lines: no file is overwritten by a restore.
#pragma once
#include <cstddef>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "editor/script.h"

namespace anisurf::editor {

// $XDG_STATE_HOME/anisurf, else ~/.local/state/anisurf, else the temporary
// directory's anisurf/.
std::string autosave_dir();

// The file name of the autosave of a session on `input` (a mesh path; its
// stem, other characters than letters, digits, '-', '_' and '.' replaced by
// '_'; "session" when empty) started at `start` (local time) by process `pid`.
std::string autosave_name(const std::string& input, std::time_t start, long pid);

// True for a name autosave_name() gives (what prune_autosaves may remove).
bool is_autosave_name(const std::string& filename);

// True when a journal holds work worth keeping: a line that is not `open`,
// `save`, `screenshot`, `quit` or a comment.
bool journal_has_edits(const std::vector<std::string>& journal);

struct AutosaveEntry {
  std::string path;
  std::string input;    // the MESH of the script's first `open` line ("" if none)
  std::string started;  // "2026-12-02 04:03:12" from the name ("" if not named so)
  std::filesystem::file_time_type written{};
  int edits = 0;        // lines journal_has_edits() counts
  int unsaved = 0;      // of those, the ones after the last `save` line
  // "bunny.off, started 2026-12-02 04:03:12, 12 edits (3 unsaved)"
  std::string describe() const;
};

// The .anisurf files of `dir`, newest first (modification time), `except`
// left out (the running session's own file). Unreadable files are skipped.
std::vector<AutosaveEntry> list_autosaves(const std::string& dir, const std::string& except = {});

// Removes the oldest autosaves of `dir` (files named by autosave_name) beyond
// the newest `keep`, never `except`. Returns how many were removed.
int prune_autosaves(const std::string& dir, std::size_t keep, const std::string& except = {});

// The lines of an autosave a restore replays (every line but `save`,
// `screenshot` and `quit`); `skipped` receives how many were left out.
// Throws Error if the file cannot be read.
std::vector<ScriptLine> restorable_lines(const std::string& path, int* skipped = nullptr);

// Replays an autosave into `session` (restorable_lines, each executed and
// waited for). Throws Error naming the line that failed; the session then
// holds what was replayed before it. Returns how many lines were skipped.
int restore_autosave(const std::string& path, EditorSession& session, ViewState& view);

// The autosave of one launch. write() saves the journal when it changed and
// holds edits; the first write picks the file name from the journal's first
// `open` line and creates the file exclusively (a name already present gets
// "-2", "-3" ... before the extension); later writes replace its content
// through a temporary file renamed over it.
class Autosave {
 public:
  Autosave(std::string dir, std::time_t start, long pid);
  // Returns true if the file was written; throws Error (naming the file and
  // the cause) when it could not be; the next call tries again.
  bool write(const std::vector<std::string>& journal);
  // The file, "" until the first write.
  const std::string& path() const { return path_; }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  std::time_t start_;
  long pid_;
  std::string path_;
  std::vector<std::string> written_;  // the journal as last written
};

}  // namespace anisurf::editor
