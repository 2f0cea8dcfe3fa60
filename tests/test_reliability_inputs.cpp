// Input paths that are not files: a directory with a mesh or .sol extension
// is refused naming it, for every reader.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "core/error.h"
#include "io/mesh_io.h"
#include "test_util.h"

using namespace anisurf;

TEST_CASE("readers: a directory named like a mesh or a .sol is refused by name") {
  const auto dir = test::temp_dir("reader_directory_input");
  for (const char* name : {"d.mesh", "d.meshb", "d.obj", "d.off", "d.ply", "d.stl", "d.gltf", "d.glb"}) {
    const std::string path = (dir / name).string();
    std::filesystem::create_directories(path);
    CAPTURE(path);
    CHECK_THROWS_WITH_AS(read_mesh_data(path), (path + ": is a directory, expected a file").c_str(), IoError);
  }
  for (const char* name : {"d.sol", "d.solb"}) {
    const std::string path = (dir / name).string();
    std::filesystem::create_directories(path);
    CAPTURE(path);
    CHECK_THROWS_WITH_AS(read_sol(path), (path + ": is a directory, expected a file").c_str(), IoError);
  }
}
