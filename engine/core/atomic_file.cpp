#include "core/atomic_file.h"

#include <filesystem>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace anisurf {

AtomicFile::AtomicFile(const std::string& path)
    : path_(path), tmp_(path + ".tmp-" + std::to_string(::getpid())) {
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw IoError(path_ + ": cannot open for writing (" + std::strerror(errno) + ")");
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::remove(tmp_.c_str());
  }
}

namespace {

// Flushes a closed file's data to the disk; throws IoError naming `shown`.
void sync_file(const std::string& path, const std::string& shown) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw IoError(shown + ": cannot reopen the written file (" + std::strerror(errno) + ")");
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw IoError(shown + ": cannot flush the file to disk (" + std::strerror(err) + ")");
}

// True when `s` is all digits naming a process that no longer runs.
bool is_dead_pid(const std::string& s) {
  if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) return false;
  const pid_t pid = static_cast<pid_t>(std::stol(s));
  return pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH;
}

// Flushes a directory's entries (the renames and creations in it) to disk;
// best effort: some file systems refuse fsync on a directory.
void sync_directory(const std::string& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::string directory_of(const std::string& path) {
  const std::filesystem::path p = std::filesystem::path(path).parent_path();
  return p.empty() ? std::string(".") : p.string();
}

constexpr const char* kRecordTag = ".commit-";
constexpr const char* kRecordPartTag = ".part";

// Parses a commit record: one "temporary\ttarget" line per file, then a line
// "end" (absent when the writer died while writing the record: returns false).
bool read_commit_record(const std::string& record, std::vector<std::pair<std::string, std::string>>& renames) {
  std::ifstream in(record, std::ios::binary);
  std::string line;
  while (std::getline(in, line)) {
    if (line == "end") return true;
    const std::size_t tab = line.find('\t');
    if (tab == std::string::npos) return false;
    renames.emplace_back(line.substr(0, tab), line.substr(tab + 1));
  }
  return false;
}

}  // namespace

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw IoError(path_ + ": write failed (disk full or permission denied?)");
  out_.close();
  sync_file(tmp_, path_);
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw IoError(path_ + ": cannot rename temporary file (" + std::strerror(errno) + ")");
  committed_ = true;
}

void check_writable(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, not a file to write");
  const std::string probe = path + ".tmp-" + std::to_string(::getpid());
  std::ofstream out(probe, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(path + ": cannot be written (" + std::strerror(errno) + ")");
  out.close();
  std::remove(probe.c_str());
}

std::string OutputSet::temporary(const std::string& path) {
  const std::filesystem::path p(path);
  std::filesystem::path tmp = p;
  tmp.replace_filename(p.stem().string() + ".tmp-" + std::to_string(::getpid()) + p.extension().string());
  files_.emplace_back(tmp.string(), path);
  return files_.back().first;
}

std::string OutputSet::write_commit_record() const {
  namespace fs = std::filesystem;
  const fs::path first(files_.front().second);
  const std::string record =
      (fs::path(directory_of(first.string())) / (first.stem().string() + kRecordTag + std::to_string(::getpid()))).string();
  const std::string part = record + kRecordPartTag;
  {
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    for (const auto& [tmp, path] : files_) out << fs::absolute(tmp).string() << '\t' << fs::absolute(path).string() << '\n';
    out << "end\n";
    out.flush();
    if (!out) {
      std::remove(part.c_str());
      throw IoError(record + ": cannot write the commit record (disk full or permission denied?)");
    }
  }
  try {
    sync_file(part, record);
  } catch (...) {
    std::remove(part.c_str());
    throw;
  }
  if (std::rename(part.c_str(), record.c_str()) != 0) {
    std::remove(part.c_str());
    throw IoError(record + ": cannot rename the commit record (" + std::strerror(errno) + ")");
  }
  sync_directory(directory_of(record));
  return record;
}

void OutputSet::commit() {
  for (const auto& [tmp, path] : files_) sync_file(tmp, path);
  const std::string record = files_.size() > 1 ? write_commit_record() : std::string();
  for (const auto& [tmp, path] : files_)
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      throw IoError(path + ": cannot rename its temporary file (" + std::strerror(errno) + ")");
  committed_ = true;
  if (!record.empty()) {
    for (const auto& f : files_) sync_directory(directory_of(f.second));
    std::remove(record.c_str());
  }
}

int finish_interrupted_commits(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  int finished = 0;
  for (const auto& entry : fs::directory_iterator(directory_of(path), ec)) {
    const std::string f = entry.path().filename().string();
    const std::size_t at = f.rfind(kRecordTag);
    if (at == std::string::npos) continue;
    std::string pid = f.substr(at + std::string(kRecordTag).size());
    const bool part = pid.size() > std::string(kRecordPartTag).size() &&
                      pid.compare(pid.size() - std::string(kRecordPartTag).size(), std::string::npos, kRecordPartTag) == 0;
    if (part) pid.resize(pid.size() - std::string(kRecordPartTag).size());
    if (!is_dead_pid(pid)) continue;
    std::vector<std::pair<std::string, std::string>> renames;
    if (!part && read_commit_record(entry.path().string(), renames)) {
      for (const auto& [tmp, target] : renames)
        if (fs::exists(tmp, ec) && std::rename(tmp.c_str(), target.c_str()) != 0)
          throw IoError(target + ": cannot complete an interrupted write (renaming " + tmp + ": " +
                        std::strerror(errno) + ")");
      ++finished;
    }
    fs::remove(entry.path(), ec);
  }
  return finished;
}

OutputSet::~OutputSet() {
  if (committed_) return;
  for (const auto& f : files_) std::remove(f.first.c_str());
}

int remove_stale_temporaries(const std::string& path) {
  namespace fs = std::filesystem;
  finish_interrupted_commits(path);
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  const std::string name = p.filename().string(), stem = p.stem().string(), ext = p.extension().string();
  std::error_code ec;
  int removed = 0;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string f = entry.path().filename().string();
    std::string pid;
    const std::string atomic_prefix = name + ".tmp-", set_prefix = stem + ".tmp-";
    if (f.rfind(atomic_prefix, 0) == 0)
      pid = f.substr(atomic_prefix.size());
    else if (f.rfind(set_prefix, 0) == 0) {
      // "<stem>.tmp-<pid><ext>", or the writer's own "<...><ext>.tmp-<pid>" of it
      const std::size_t at = ext.empty() ? f.size() : f.find(ext, set_prefix.size());
      const std::string rest = at == std::string::npos ? std::string("?") : f.substr(at + ext.size());
      if (rest.empty() || (rest.rfind(".tmp-", 0) == 0 && is_dead_pid(rest.substr(5))))
        pid = f.substr(set_prefix.size(), at - set_prefix.size());
    }
    if (is_dead_pid(pid) && fs::is_regular_file(entry.path(), ec) && fs::remove(entry.path(), ec)) ++removed;
  }
  return removed;
}

}  // namespace anisurf
