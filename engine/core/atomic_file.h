// Writes a file through a temporary sibling that is renamed over the target on
// commit(), so that a failed write never leaves a half-written output.
#pragma once
#include <fstream>
#include <string>

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

// Checks before a long computation that `path` can be written as AtomicFile
// writes it: not a directory, and its directory exists and accepts a new
// file (a probe file is created and removed). Throws IoError naming the path.
void check_writable(const std::string& path);

}  // namespace anisurf
