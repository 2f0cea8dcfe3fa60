#include "core/atomic_file.h"

#include <filesystem>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

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

void OutputSet::commit() {
  for (const auto& [tmp, path] : files_) sync_file(tmp, path);
  for (const auto& [tmp, path] : files_)
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      throw IoError(path + ": cannot rename its temporary file (" + std::strerror(errno) + ")");
  committed_ = true;
}

OutputSet::~OutputSet() {
  if (committed_) return;
  for (const auto& f : files_) std::remove(f.first.c_str());
}

int remove_stale_temporaries(const std::string& path) {
  namespace fs = std::filesystem;
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
