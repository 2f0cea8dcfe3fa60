// The fuzzing corpus replayed through the same entry functions as the
// libFuzzer targets (tests/fuzz/fuzz_entry.h): every file of tests/data (good
// and bad/), assets/ and tests/fuzz/corpus/READER/ (seeds and every crash
// reproducer found so far) is either read into a mesh whose validate() holds
// or refused with anisurf::Error; any other exception or a crash fails.
#include <doctest/doctest.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "fuzz/fuzz_entry.h"

using namespace anisurf::fuzz;
namespace fs = std::filesystem;

namespace {

struct CorpusFile {
  fs::path path;
  Reader reader;
};

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Files whose extension names a reader.
std::vector<CorpusFile> by_extension(const fs::path& dir) {
  std::vector<CorpusFile> out;
  for (const fs::path& f : files_in(dir))
    if (const auto r = reader_of(f.filename().string())) out.push_back({f, *r});
  return out;
}

// tests/fuzz/corpus/NAME/*: read by the reader NAME, whatever the file name.
std::vector<CorpusFile> fuzz_corpus() {
  std::vector<CorpusFile> out;
  for (Reader r : all_readers())
    for (const fs::path& f : files_in(fs::path(ANISURF_FUZZ_CORPUS_DIR) / reader_name(r))) out.push_back({f, r});
  return out;
}

// Replays `files`; returns how many were read into a mesh.
int replay(const std::vector<CorpusFile>& files) {
  int loaded = 0;
  for (const CorpusFile& f : files) {
    const std::string file = f.path.string();
    const std::string reader = reader_name(f.reader);
    CAPTURE(file);
    CAPTURE(reader);
    try {
      const Result r = read_file(f.reader, file);
      CHECK_MESSAGE(r.outcome != Outcome::Invalid, r.message);
      loaded += r.outcome == Outcome::Loaded;
    } catch (const std::exception& e) {
      FAIL_CHECK("an exception other than anisurf::Error: " << e.what());
    } catch (...) {
      FAIL_CHECK("a non-standard exception");
    }
  }
  return loaded;
}

}  // namespace

TEST_CASE("fuzz corpus: the test data's good files load into valid meshes") {
  const auto good = by_extension(ANISURF_TEST_DATA_DIR);
  const auto assets = by_extension(fs::path(ANISURF_TEST_DATA_DIR) / ".." / ".." / "assets");
  REQUIRE(good.size() >= 8);
  CHECK(replay(good) == static_cast<int>(good.size()));
  CHECK(replay(assets) == static_cast<int>(assets.size()));
}

TEST_CASE("fuzz corpus: the bad files are refused with anisurf::Error or load valid") {
  const auto bad = by_extension(fs::path(ANISURF_TEST_DATA_DIR) / "bad");
  REQUIRE(bad.size() >= 40);
  replay(bad);
}

TEST_CASE("fuzz corpus: seeds and crash reproducers of tests/fuzz/corpus") {
  const auto corpus = fuzz_corpus();
  MESSAGE(corpus.size() << " files in tests/fuzz/corpus");
  replay(corpus);
}

TEST_CASE("fuzz corpus: every reader's entry function takes empty and garbage input") {
  const std::string garbage = "\x7f\xff solid endsolid ply\nformat ascii 1.0\n{\"asset\":";
  for (Reader r : all_readers()) {
    CAPTURE(reader_name(r));
    CHECK(read_bytes(r, nullptr, 0).outcome == Outcome::Refused);
    CHECK(read_bytes(r, reinterpret_cast<const std::uint8_t*>(garbage.data()), garbage.size()).outcome ==
          Outcome::Refused);
  }
}
