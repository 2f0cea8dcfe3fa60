// The `anisurf` program as a user runs it: help texts, info --json, convert,
// and bad input giving a clear message and a non-zero exit.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_util.h"

namespace {

struct Run {
  int code;
  std::string out;
  std::string err;
};

Run run_anisurf(const std::string& args, const std::string& tag) {
  auto dir = anisurf::test::temp_dir("cli_" + tag);
  std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string();
  std::string cmd = std::string("\"") + ANISURF_BINARY + "\" " + args + " >" + out + " 2>" + err;
  int status = std::system(cmd.c_str());
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

std::string demo_mesh() { return std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.mesh"; }

}  // namespace

TEST_CASE("anisurf --help lists the commands, each has its own help with an example") {
  Run r = run_anisurf("--help", "help");
  CHECK(r.code == 0);
  CHECK(r.out.find("info") != std::string::npos);
  CHECK(r.out.find("convert") != std::string::npos);
  for (const char* c : {"info", "convert"}) {
    Run h = run_anisurf(std::string(c) + " --help", std::string("help_") + c);
    CHECK(h.code == 0);
    CHECK(h.out.find("usage: anisurf") != std::string::npos);
    CHECK(h.out.find("example:") != std::string::npos);
  }
  Run bad = run_anisurf("frobnicate", "unknown");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("unknown command") != std::string::npos);
}

TEST_CASE("anisurf info --json on the demo") {
  Run r = run_anisurf("info " + demo_mesh() + " --json", "info_json");
  REQUIRE(r.code == 0);
  for (const char* key : {"\"vertices\": 162", "\"triangles\": 320", "\"bbox\"", "\"euler_characteristic\": 2",
                          "\"components\": 1", "\"valid\": true"})
    CHECK_MESSAGE(r.out.find(key) != std::string::npos, key);
}

TEST_CASE("anisurf convert writes every output format, then reads it back") {
  auto dir = anisurf::test::temp_dir("cli_convert");
  for (const char* ext : {".mesh", ".meshb", ".obj", ".ply", ".stl", ".glb"}) {
    std::string out = (dir / (std::string("demo") + ext)).string();
    Run r = run_anisurf("convert " + demo_mesh() + " " + out, std::string("convert") + (ext + 1));
    CAPTURE(ext);
    CAPTURE(r.err);
    REQUIRE(r.code == 0);
    Run i = run_anisurf("info " + out + " --json", std::string("reinfo") + (ext + 1));
    CHECK(i.code == 0);
    CHECK(i.out.find("\"vertices\": 162") != std::string::npos);
    CHECK(i.out.find("\"triangles\": 320") != std::string::npos);
  }
  // fields: the demo metric goes into a .sol beside a Medit output and into a .vtk
  std::string sol = std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.sol";
  Run r = run_anisurf("convert " + demo_mesh() + " " + (dir / "withsol.mesh").string() + " --sol " + sol, "convsol");
  CHECK(r.code == 0);
  CHECK(std::filesystem::exists(dir / "withsol.sol"));
  Run v = run_anisurf("convert " + demo_mesh() + " " + (dir / "demo.vtk").string() + " --sol " + sol, "convvtk");
  CHECK(v.code == 0);
  CHECK(std::filesystem::file_size(dir / "demo.vtk") > 1000);
}

TEST_CASE("bad input: clear message, non-zero exit, no output left behind") {
  auto dir = anisurf::test::temp_dir("cli_bad");
  std::string missing = (dir / "nope.mesh").string();
  Run r = run_anisurf("info " + missing, "missing");
  CHECK(r.code == 1);
  CHECK(r.err.find("nope.mesh") != std::string::npos);

  Run ext = run_anisurf("info " + (dir / "x.xyz").string(), "ext");
  CHECK(ext.code == 1);
  CHECK(ext.err.find("unknown mesh format") != std::string::npos);

  // a truncated file: nothing written for convert
  std::string broken = (dir / "broken.mesh").string();
  {
    std::ofstream o(broken);
    o << "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n";
  }
  std::string out = (dir / "out.obj").string();
  Run c = run_anisurf("convert " + broken + " " + out, "conv_broken");
  CHECK(c.code == 1);
  CHECK(c.err.find("broken.mesh") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
  for (const auto& e : std::filesystem::directory_iterator(dir))
    CHECK_MESSAGE(e.path().string().find(".tmp-") == std::string::npos, e.path().string());

  Run usage = run_anisurf("convert onlyone.mesh", "usage");
  CHECK(usage.code == 2);
}
