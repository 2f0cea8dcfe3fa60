// Writes a file through a temporary sibling that is renamed over the target on
// commit(), so that a failed write never leaves a half-written output.
#pragma once
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace anisurf {

class AtomicFile {
 public:
  // Opens "<path>.tmp-<pid>" for writing (binary); throws IoError on failure.
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  // Flushes, closes and renames over the target; throws IoError on failure.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Outputs that belong together (a mesh and its .sol): each is written to a
// temporary sibling with the same extension ("out.tmp-<pid>.mesh"), then
// commit() flushes every temporary to disk and renames them all, back to
// back; a failure before the renames (or destruction without commit) removes
// the temporaries and leaves the previous outputs as they were.
// A set of several files is committed through a record
// ("<first stem>.commit-<pid>" beside the first output, listing each
// temporary and its target) written and flushed before the first rename and
// removed after the last: a process killed between two renames leaves the
// record, and finish_interrupted_commits() completes its renames.
class OutputSet {
 public:
  OutputSet() = default;
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // The temporary path to write `path` to.
  std::string temporary(const std::string& path);
  // fsync of every temporary, then the renames; throws IoError naming the file.
  void commit();

 private:
  // Writes and flushes the record of the renames to come; returns its path.
  std::string write_commit_record() const;

  std::vector<std::pair<std::string, std::string>> files_;  // temporary, final
  bool committed_ = false;
};

// Completes the commits of dead processes recorded in `path`'s directory:
// every temporary a record lists that still exists is renamed over its
// target, then the record is removed (a record that was not complete when
// its process died is removed alone: its renames never started). Returns how
// many records were completed; throws IoError naming the file a rename fails
// for.
int finish_interrupted_commits(const std::string& path);

// Completes the interrupted commits of `path`'s directory
// (finish_interrupted_commits), then removes the temporaries of `path`
// ("<path>.tmp-<pid>" of AtomicFile, "<stem>.tmp-<pid><ext>" of OutputSet)
// left by processes that no longer run (killed during a write); returns how
// many temporaries were removed.
int remove_stale_temporaries(const std::string& path);

// Checks before a long computation that `path` can be written as AtomicFile
// writes it: not a directory, and its directory exists and accepts a new
// file (a probe file is created and removed). Throws IoError naming the path.
void check_writable(const std::string& path);

}  // namespace anisurf
