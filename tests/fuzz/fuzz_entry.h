// The readers as fuzzing entry points, shared by the libFuzzer targets
// (tests/fuzz/fuzz_*.cpp, built with ANISURF_FUZZ=ON) and the corpus replay
// test (tests/test_reliability_fuzz_corpus.cpp, always built): the bytes are
// written to a file with the reader's extension and read as a user's file is,
// then built into a mesh whose invariants are checked.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace anisurf::fuzz {

enum class Reader { Medit, MeditBinary, Sol, SolBinary, Obj, Off, Ply, Stl, Gltf, Glb, Gmsh, Vtu, Vtp, Vtk };

// Every reader, its name (the fuzz target is fuzz_NAME, its corpus
// tests/fuzz/corpus/NAME) and the file extension it reads.
const std::vector<Reader>& all_readers();
const char* reader_name(Reader r);
const char* reader_extension(Reader r);
// The reader of a file name's extension (case-insensitive), if any.
std::optional<Reader> reader_of(const std::string& file_name);

// What became of one input.
enum class Outcome {
  Loaded,   // read and built: the mesh's validate() holds (fields: consistent sizes)
  Refused,  // anisurf::Error thrown (the message is in `message`)
  Invalid,  // read and built, but the result breaks an invariant (a bug)
};
struct Result {
  Outcome outcome = Outcome::Loaded;
  std::string message;
};

// Reads `size` bytes as a file of reader `r` (then builds the mesh). Any
// exception other than anisurf::Error propagates: that is a bug too.
Result read_bytes(Reader r, const std::uint8_t* data, std::size_t size);
// Reads a file as reader `r` (the corpus replay).
Result read_file(Reader r, const std::string& path);

}  // namespace anisurf::fuzz
