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
  std::vector<std::pair<std::string, std::string>> files_;  // temporary, final
  bool committed_ = false;
};

// Removes the temporaries of `path` ("<path>.tmp-<pid>" of AtomicFile,
// "<stem>.tmp-<pid><ext>" of OutputSet) left by processes that no longer
// run (killed during a write); returns how many.
int remove_stale_temporaries(const std::string& path);

// Checks before a long computation that `path` can be written as AtomicFile
// writes it: not a directory, and its directory exists and accepts a new
// file (a probe file is created and removed). Throws IoError naming the path.
void check_writable(const std::string& path);

}  // namespace anisurf
