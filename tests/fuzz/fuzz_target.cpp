// A libFuzzer target for one reader, chosen at compile time by
// ANISURF_FUZZ_READER (an anisurf::fuzz::Reader, see CMakeLists.txt). An input
// that builds an invalid mesh aborts; any exception other than anisurf::Error
// escapes and terminates: both are findings.
#include <cstdio>
#include <cstdlib>

#include "fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace anisurf::fuzz;
  const Result r = read_bytes(Reader::ANISURF_FUZZ_READER, data, size);
  if (r.outcome == Outcome::Invalid) {
    std::fprintf(stderr, "anisurf fuzz: the input built an invalid mesh:\n%s\n", r.message.c_str());
    std::abort();
  }
  return 0;
}
