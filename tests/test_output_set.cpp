// Outputs written as a set (core/atomic_file.h): all replaced or none, no
// temporary left behind, temporaries of killed runs removed by the next one.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "test_util.h"

using namespace anisurf;

namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int temporaries_in(const std::filesystem::path& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) ++n;
  return n;
}

// A pid no process has (above any pid_max).
constexpr const char* kDeadPid = "999999999";

}  // namespace

TEST_CASE("output set: committed files replace the old ones together, uncommitted ones leave them") {
  const auto dir = test::temp_dir("output_set");
  const std::string a = (dir / "out.mesh").string(), b = (dir / "out.sol").string();
  std::ofstream(a) << "old mesh";
  std::ofstream(b) << "old sol";
  {
    OutputSet set;
    std::ofstream(set.temporary(a)) << "new mesh";
    std::ofstream(set.temporary(b)) << "new sol";
    CHECK(slurp(a) == "old mesh");  // nothing replaced before commit
    CHECK(temporaries_in(dir) == 2);
  }  // destroyed without commit: the temporaries go, the old pair stays
  CHECK(slurp(a) == "old mesh");
  CHECK(slurp(b) == "old sol");
  CHECK(temporaries_in(dir) == 0);
  {
    OutputSet set;
    const std::string ta = set.temporary(a), tb = set.temporary(b);
    CHECK(std::filesystem::path(ta).extension() == ".mesh");  // the format follows the extension
    CHECK(std::filesystem::path(tb).extension() == ".sol");
    std::ofstream(ta) << "new mesh";
    std::ofstream(tb) << "new sol";
    set.commit();
  }
  CHECK(slurp(a) == "new mesh");
  CHECK(slurp(b) == "new sol");
  CHECK(temporaries_in(dir) == 0);
  // A temporary that was never written: commit fails naming the file and
  // replaces nothing.
  {
    OutputSet set;
    std::ofstream(set.temporary(a)) << "newer mesh";
    set.temporary(b);
    CHECK_THROWS_WITH_AS(set.commit(), doctest::Contains("out.sol"), IoError);
  }
  CHECK(slurp(a) == "new mesh");
  CHECK(temporaries_in(dir) == 0);
}

TEST_CASE("output set: temporaries of dead processes are removed, a live one's kept") {
  const auto dir = test::temp_dir("output_set_stale");
  const std::string out = (dir / "out.mesh").string();
  const std::string live = std::to_string(::getpid());
  for (const std::string& name : {std::string("out.mesh.tmp-") + kDeadPid, std::string("out.tmp-") + kDeadPid + ".mesh",
                                  std::string("out.tmp-") + kDeadPid + ".mesh.tmp-" + kDeadPid,
                                  "out.mesh.tmp-" + live, "other.mesh.tmp-" + std::string(kDeadPid)})
    std::ofstream(dir / name) << "x";
  CHECK(remove_stale_temporaries(out) == 3);
  CHECK(std::filesystem::exists(dir / ("out.mesh.tmp-" + live)));
  CHECK(std::filesystem::exists(dir / ("other.mesh.tmp-" + std::string(kDeadPid))));
}

TEST_CASE("output set: a commit interrupted between its renames is completed from its record") {
  const auto dir = test::temp_dir("output_set_record");
  const std::string a = (dir / "out.mesh").string(), b = (dir / "out.sol").string();
  const std::string ta = (dir / (std::string("out.tmp-") + kDeadPid + ".mesh")).string();
  const std::string tb = (dir / (std::string("out.tmp-") + kDeadPid + ".sol")).string();
  // A dead writer's state after its first rename: the new mesh in place, the
  // new sol still in its temporary, the record listing both.
  std::ofstream(a) << "new mesh";
  std::ofstream(b) << "old sol";
  std::ofstream(tb) << "new sol";
  std::ofstream(dir / (std::string("out.commit-") + kDeadPid)) << ta << '\t' << a << '\n' << tb << '\t' << b << "\nend\n";
  // A record a dead writer did not finish writing, and a live writer's record.
  std::ofstream(dir / (std::string("other.commit-") + kDeadPid + ".part")) << ta << '\t' << a << '\n';
  const std::string live = "out.commit-" + std::to_string(::getpid());
  std::ofstream(dir / live) << tb << '\t' << b << "\nend\n";
  CHECK(finish_interrupted_commits(a) == 1);
  CHECK(slurp(a) == "new mesh");
  CHECK(slurp(b) == "new sol");
  CHECK_FALSE(std::filesystem::exists(tb));
  CHECK_FALSE(std::filesystem::exists(dir / (std::string("out.commit-") + kDeadPid)));
  CHECK_FALSE(std::filesystem::exists(dir / (std::string("other.commit-") + kDeadPid + ".part")));
  CHECK(std::filesystem::exists(dir / live));  // its writer still runs
  std::filesystem::remove(dir / live);
  // A committed set leaves no record behind.
  {
    OutputSet set;
    std::ofstream(set.temporary(a)) << "newer mesh";
    std::ofstream(set.temporary(b)) << "newer sol";
    set.commit();
  }
  CHECK(slurp(b) == "newer sol");
  for (const auto& e : std::filesystem::directory_iterator(dir))
    CHECK(e.path().filename().string().find(".commit-") == std::string::npos);
}

TEST_CASE("anisurf adapt: mesh and metric written as a pair, a killed run's temporaries removed") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("adapt_pair");
  std::ofstream(dir / (std::string("out.tmp-") + kDeadPid + ".mesh")) << "half a mesh";
  std::ofstream(dir / (std::string("out.sol.tmp-") + kDeadPid)) << "half a sol";
  int status = -1;
  test::capture(std::string(ANISURF_BINARY) + " adapt '" + mesh + "' -sol '" + sol + "' -v 0 -o '" +
                    (dir / "out.mesh").string() + "'",
                &status);
  REQUIRE(status == 0);
  CHECK(temporaries_in(dir) == 0);
  const SurfaceMesh m = load_mesh((dir / "out.mesh").string());
  CHECK(read_sol((dir / "out.sol").string(), m.n_vertices()).size() == 1);  // one value per vertex
}
