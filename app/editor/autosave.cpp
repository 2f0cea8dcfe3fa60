#include "editor/autosave.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace anisurf::editor {

namespace {

namespace fs = std::filesystem;

const char* kHeader = "# anisurf editor session (autosave): replay with anisurf --script ";

bool all_digits(const std::string& s, std::size_t from, std::size_t n) {
  if (from + n > s.size()) return false;
  for (std::size_t i = from; i < from + n; ++i)
    if (s[i] < '0' || s[i] > '9') return false;
  return true;
}

// The command word of a journal line ("" for a comment or a blank line).
std::string command_of(const std::string& line) {
  const auto words = split_words(line);
  return words.empty() ? std::string() : words[0];
}

bool counts_as_edit(const std::string& cmd) {
  return !cmd.empty() && cmd != "open" && cmd != "save" && cmd != "screenshot" && cmd != "quit";
}

// Parses <stem>-YYYYmmdd-HHMMSS-PID[-N].anisurf; `start` receives
// "YYYY-mm-dd HH:MM:SS".
bool parse_autosave_name(const std::string& f, std::string* start) {
  const std::string ext = ".anisurf";
  if (f.size() <= ext.size() || f.compare(f.size() - ext.size(), ext.size(), ext) != 0) return false;
  std::string base = f.substr(0, f.size() - ext.size());
  auto strip_number = [&] {
    const auto dash = base.rfind('-');
    if (dash == std::string::npos || dash + 1 == base.size() || !all_digits(base, dash + 1, base.size() - dash - 1))
      return false;
    base.resize(dash);
    return true;
  };
  if (!strip_number()) return false;  // the PID, or N
  for (int attempt = 0; attempt < 2; ++attempt) {
    const std::size_t n = base.size();
    if (n >= 17 && base[n - 16] == '-' && all_digits(base, n - 15, 8) && base[n - 7] == '-' && all_digits(base, n - 6, 6)) {
      if (start) {
        const std::string d = base.substr(n - 15, 8), t = base.substr(n - 6, 6);
        *start = d.substr(0, 4) + "-" + d.substr(4, 2) + "-" + d.substr(6, 2) + " " + t.substr(0, 2) + ":" +
                 t.substr(2, 2) + ":" + t.substr(4, 2);
      }
      return true;
    }
    if (attempt == 0 && !strip_number()) return false;  // that was N: now the PID
  }
  return false;
}

}  // namespace

std::string autosave_dir() {
  const char* state = std::getenv("XDG_STATE_HOME");
  const char* home = std::getenv("HOME");
  const fs::path base = state && *state ? fs::path(state)
                        : home && *home  ? fs::path(home) / ".local" / "state"
                                         : fs::temp_directory_path();
  return (base / "anisurf").string();
}

std::string autosave_name(const std::string& input, std::time_t start, long pid) {
  std::string stem = fs::path(input).stem().string();
  for (char& c : stem)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  if (stem.empty()) stem = "session";
  std::tm tm{};
  localtime_r(&start, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
  return stem + "-" + stamp + "-" + std::to_string(pid) + ".anisurf";
}

bool is_autosave_name(const std::string& f) { return parse_autosave_name(f, nullptr); }

bool journal_has_edits(const std::vector<std::string>& journal) {
  return std::any_of(journal.begin(), journal.end(), [](const std::string& l) { return counts_as_edit(command_of(l)); });
}

std::string AutosaveEntry::describe() const {
  std::string s = input.empty() ? fs::path(path).filename().string() : fs::path(input).filename().string();
  if (!started.empty()) s += ", started " + started;
  s += ", " + std::to_string(edits) + (edits == 1 ? " edit" : " edits");
  if (unsaved < edits) s += unsaved == 0 ? " (all saved)" : " (" + std::to_string(unsaved) + " unsaved)";
  return s;
}

std::vector<AutosaveEntry> list_autosaves(const std::string& dir, const std::string& except) {
  std::vector<AutosaveEntry> out;
  std::error_code ec;
  fs::directory_iterator it(dir, ec), end;
  if (ec) return out;
  for (; it != end; it.increment(ec)) {
    if (ec) break;
    const fs::path p = it->path();
    if (p.extension() != ".anisurf" || !it->is_regular_file(ec)) continue;
    if (!except.empty() && fs::equivalent(p, except, ec)) continue;
    std::ifstream in(p);
    if (!in) continue;
    AutosaveEntry e;
    e.path = p.string();
    e.written = fs::last_write_time(p, ec);
    parse_autosave_name(p.filename().string(), &e.started);
    for (std::string line; std::getline(in, line);) {
      const auto words = split_words(line);
      if (words.empty()) continue;
      if (words[0] == "open" && words.size() > 1 && e.input.empty()) e.input = words[1];
      if (counts_as_edit(words[0])) ++e.edits, ++e.unsaved;
      if (words[0] == "save") e.unsaved = 0;
      if (words[0] == "open") e.unsaved = 0;  // a new mesh: what came before was dropped or saved
    }
    out.push_back(std::move(e));
  }
  std::sort(out.begin(), out.end(), [](const AutosaveEntry& a, const AutosaveEntry& b) {
    return a.written != b.written ? a.written > b.written : a.path > b.path;
  });
  return out;
}

int prune_autosaves(const std::string& dir, std::size_t keep, const std::string& except) {
  int removed = 0;
  std::size_t kept = 0;
  for (const AutosaveEntry& e : list_autosaves(dir, except)) {
    if (!is_autosave_name(fs::path(e.path).filename().string())) continue;
    if (kept < keep) {
      ++kept;
      continue;
    }
    std::error_code ec;
    if (fs::remove(e.path, ec)) ++removed;
  }
  return removed;
}

std::vector<ScriptLine> restorable_lines(const std::string& path, int* skipped) {
  std::vector<ScriptLine> lines = read_script(path);
  const auto n = lines.size();
  std::erase_if(lines, [](const ScriptLine& l) {
    const std::string& c = l.words[0];
    return c == "save" || c == "screenshot" || c == "quit";
  });
  if (skipped) *skipped = static_cast<int>(n - lines.size());
  return lines;
}

int restore_autosave(const std::string& path, EditorSession& session, ViewState& view) {
  int skipped = 0;
  const auto lines = restorable_lines(path, &skipped);
  if (lines.empty() || lines.front().words[0] != "open")
    throw Error(path + ": not an editor session (it does not start with open MESH)");
  for (const ScriptLine& l : lines) {
    execute(l, session, view, {});
    session.wait();
    if (const std::string err = session.adaptation_error(); !err.empty())
      throw Error(l.where() + ": " + l.words[0] + ": " + err);
  }
  return skipped;
}

Autosave::Autosave(std::string dir, std::time_t start, long pid) : dir_(std::move(dir)), start_(start), pid_(pid) {}

bool Autosave::write(const std::vector<std::string>& journal) {
  if (journal == written_ || !journal_has_edits(journal)) return false;
  if (path_.empty()) {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) throw Error("autosave: cannot create the directory " + dir_ + ": " + ec.message());
    std::string input;
    for (const auto& l : journal)
      if (const auto w = split_words(l); w.size() > 1 && w[0] == "open") {
        input = w[1];
        break;
      }
    const std::string name = autosave_name(input, start_, pid_);
    const std::string stem = name.substr(0, name.size() - std::string(".anisurf").size());
    for (int k = 1; path_.empty(); ++k) {
      const std::string candidate = (fs::path(dir_) / (k == 1 ? name : stem + "-" + std::to_string(k) + ".anisurf")).string();
      // O_EXCL: the name is ours only if no other launch holds it.
      const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
      if (fd >= 0) {
        ::close(fd);
        path_ = candidate;
      } else if (errno != EEXIST || k > 1000) {
        throw Error("autosave: cannot create " + candidate + ": " + std::strerror(errno));
      }
    }
  }
  try {
    AtomicFile f(path_);
    f.stream() << kHeader << path_ << "\n";
    for (const auto& l : journal) f.stream() << l << "\n";
    f.commit();
  } catch (const std::exception& e) {
    throw Error(std::string("autosave: ") + e.what());
  }
  written_ = journal;
  return true;
}

}  // namespace anisurf::editor
