// anisurf_replay: every file given (or found in the directories given) whose
// extension names a reader, and every file of a directory named like a
// reader (tests/fuzz/corpus/READER/), read through the fuzzing entry
// functions (fuzz_entry.h). Built with the sanitizers by
// scripts/sanitize-readers.sh, the readers' part of CI under ASan + UBSan.
// Prints one line per reader (files read, loaded, refused); exits 1 when an
// input builds an invalid mesh or throws anything but anisurf::Error (a
// sanitizer report aborts by itself).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fuzz_entry.h"

using namespace anisurf::fuzz;
namespace fs = std::filesystem;

namespace {

struct Counts {
  int files = 0, loaded = 0, refused = 0;
};

std::optional<Reader> reader_named(const std::string& name) {
  for (Reader r : all_readers())
    if (name == reader_name(r)) return r;
  return std::nullopt;
}

// The files under `root` with their reader: by the directory's name for a
// corpus directory, else by extension; sorted for a stable order.
std::vector<std::pair<fs::path, Reader>> inputs_under(const fs::path& root) {
  std::vector<std::pair<fs::path, Reader>> out;
  std::error_code ec;
  if (fs::is_regular_file(root, ec)) {
    if (const auto r = reader_of(root.filename().string())) out.push_back({root, *r});
    return out;
  }
  for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    const fs::path& p = it->path();
    if (const auto by_dir = reader_named(p.parent_path().filename().string()))
      out.push_back({p, *by_dir});
    else if (const auto by_ext = reader_of(p.filename().string()))
      out.push_back({p, *by_ext});
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: anisurf_replay FILE_OR_DIR...\n");
    return 2;
  }
  std::map<std::string, Counts> counts;
  int failures = 0;
  for (int i = 1; i < argc; ++i)
    for (const auto& [path, reader] : inputs_under(argv[i])) {
      Counts& c = counts[reader_name(reader)];
      ++c.files;
      try {
        const Result r = read_file(reader, path.string());
        if (r.outcome == Outcome::Loaded) ++c.loaded;
        if (r.outcome == Outcome::Refused) ++c.refused;
        if (r.outcome == Outcome::Invalid) {
          std::fprintf(stderr, "replay: %s (%s): invalid mesh: %s\n", path.c_str(), reader_name(reader),
                       r.message.c_str());
          ++failures;
        }
      } catch (const std::exception& e) {
        std::fprintf(stderr, "replay: %s (%s): unexpected exception: %s\n", path.c_str(), reader_name(reader),
                     e.what());
        ++failures;
      }
    }
  int total = 0;
  for (const auto& [name, c] : counts) {
    std::printf("replay %-6s %5d files  %5d loaded  %5d refused\n", name.c_str(), c.files, c.loaded, c.refused);
    total += c.files;
  }
  std::printf("replay: %d files, %d failures\n", total, failures);
  return failures == 0 && total > 0 ? 0 : 1;
}
